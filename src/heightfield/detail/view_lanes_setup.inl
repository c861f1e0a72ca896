// The pixel directions of RaySetup::operator() (grid_ray.hpp) for a row of pixels in SIMD lanes:
// the same IEEE operations in the same order (muld never fuses with addd), so every lane is the
// scalar value bit for bit. Included by view_trace_simd.cpp after the lane operations.

BT_LANES void directions(const DirectionFrame& f, const double* u, double v, int count,
                         RowDirections& out) {
    alignas(64) double uu[kRowDirections] = {};
    for (int i = 0; i < count; ++i) {
        uu[i] = u[i];
    }
    const D vv = set1d(v);
    const D one = set1d(1.0), zero = set1d(0.0), inf = set1d(kInf), per_cell = set1d(f.per_cell);
    for (int k = 0; k < kRowDirections; k += kLanes) {
        const D uk = load(uu + k);
        // forward + right * u + up * v, then normalize: a * (1 / sqrt(dot(a, a))).
        const D ax = addd(addd(set1d(f.fx), muld(set1d(f.rx), uk)), muld(set1d(f.ux), vv));
        const D ay = addd(addd(set1d(f.fy), muld(set1d(f.ry), uk)), muld(set1d(f.uy), vv));
        const D az = addd(addd(set1d(f.fz), muld(set1d(f.rz), uk)), muld(set1d(f.uz), vv));
        const D len = sqrtd(addd(addd(muld(ax, ax), muld(ay, ay)), muld(az, az)));
        const D inv = divd(one, len);
        const D dx = muld(muld(ax, inv), per_cell);
        const D dy = muld(muld(ay, inv), per_cell);
        const D dz = muld(az, inv);
        store(out.dx + k, dx);
        store(out.dy + k, dy);
        store(out.dz + k, dz);
        store(out.inv_dx + k, seld(eqd(dx, zero), inf, divd(one, dx)));
        store(out.inv_dy + k, seld(eqd(dy, zero), inf, divd(one, dy)));
        store(out.inv_dz + k, divd(one, dz));
    }
}
