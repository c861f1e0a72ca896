#!/usr/bin/env python3
"""Derives the constants of src/physics/fast_exp.cpp (our e^x) from the mathematics, with mpmath
(60 digits), and prints them as C++ hexadecimal doubles:

  - ln 2 in two parts (Cody and Waite): ln2_hi, ln 2 rounded to 32 significant bits (so that
    k * ln2_hi is exact for |k| < 2^21), and ln2_lo, the rest rounded to a double;
  - 1 / ln 2, rounded;
  - q(r) = c0 + c1 r + ... + c9 r^9, the Chebyshev fit (mpmath.chebyfit: interpolation at the
    Chebyshev nodes, near minimax) of (e^r - 1 - r) / r^2 on [-0.35, 0.35] (|r| <= ln 2 / 2 plus
    a margin for the rounding of k), each coefficient rounded to a double. e^r = 1 + r + r^2 q(r)
    then errs by r^2 times the fit's error: below 0.13 ulp of the result (printed).

usage: scripts/exp_coefficients.py   (needs python3-mpmath)
"""
import mpmath as mp


def main():
    mp.mp.dps = 60
    ln2 = mp.log(2)
    ln2_hi = mp.floor(ln2 * 2**32 + mp.mpf(1) / 2) / 2**32
    ln2_lo = ln2 - ln2_hi
    print(f"kLog2e = {float(1 / ln2).hex()}")
    print(f"kLn2Hi = {float(ln2_hi).hex()}  (exact: {float(ln2_hi) == ln2_hi})")
    print(f"kLn2Lo = {float(ln2_lo).hex()}")

    half_width = mp.mpf("0.35")

    def q(r):
        if abs(r) < mp.mpf("1e-25"):  # the series' first terms: 1/2 + r/6 + ...
            return mp.mpf(1) / 2 + r / 6
        return (mp.exp(r) - 1 - r) / r**2

    coefficients, error = mp.chebyfit(q, [-half_width, half_width], 10, error=True)
    # chebyfit lists the highest power first.
    for i, c in enumerate(reversed(coefficients)):
        print(f"c{i} = {float(c).hex()}")
    ulp = mp.mpf(2) ** -53  # the ulp of a result in [0.7, 1)
    print(f"fit error {mp.nstr(error, 5)}: {mp.nstr(error * half_width**2 / ulp, 3)} ulp at most")


if __name__ == "__main__":
    main()
