#!/usr/bin/env python3
"""Derives the polynomial of src/physics/fast_exp.cpp's natural log (fast_log) from the
mathematics, with mpmath (60 digits), and prints it as C++ hexadecimal doubles.

x = 2^k m with m in [sqrt(2)/2, sqrt(2)), f = m - 1 and s = f / (2 + f), so that
ln(1 + f) = 2 atanh(s) = 2s + 2s^3/3 + 2s^5/5 + ... = 2s + s R(z), z = s^2, |s| <= 3 - 2 sqrt(2),
and R(z) = z p(z): p the Chebyshev fit (mpmath.chebyfit: interpolation at the Chebyshev nodes,
near minimax) of (2 atanh(s) - 2s) / s^3 = 2/3 + 2z/5 + 2z^2/7 + ... on [0, z_max] with a small
margin, eight coefficients, each rounded to a double. ln2_hi and ln2_lo are fast_exp's (ln 2 to
32 bits, so that k ln2_hi is exact for |k| < 2^21, and the rest). The fit's error times s (the
term's weight in ln(1 + f)) is printed in ulps of the smallest result it can touch.

usage: scripts/log_coefficients.py   (needs python3-mpmath)
"""
import mpmath as mp


def main():
    mp.mp.dps = 60
    s_max = 3 - 2 * mp.sqrt(2)  # (sqrt2 - 1) / (sqrt2 + 1)
    z_max = s_max**2 * mp.mpf("1.001")

    def p(z):
        if z < mp.mpf("1e-30"):  # the series' first terms
            return mp.mpf(2) / 3 + 2 * z / 5
        s = mp.sqrt(z)
        return (2 * mp.atanh(s) - 2 * s) / s**3

    coefficients, error = mp.chebyfit(p, [0, z_max], 8, error=True)
    for i, c in enumerate(reversed(coefficients)):  # chebyfit lists the highest power first
        print(f"c{i} = {float(c).hex()}")
    # The fit's error enters ln(1 + f) as s^3 error; ln(1 + f) >= |f| / 2 >= |s| there.
    worst = error * s_max**2 / 2 ** -53  # relative, in ulps of a result of magnitude |s|
    print(f"fit error {mp.nstr(error, 5)}: {mp.nstr(worst, 3)} ulp at most")
    print(f"sqrt(2)/2 bits: {mp.nstr(mp.sqrt(2) / 2, 20)} = {float(mp.sqrt(2) / 2).hex()}")


if __name__ == "__main__":
    main()
