// The pixel rays of RaySetup::operator() and RaySetup::clip (grid_ray.hpp) for a row of pixels in
// SIMD lanes: the same IEEE operations in the same order (muld never fuses with addd) and the
// same choices where std::min, std::max and std::clamp differ from the min and max instructions
// (ties of signed zeros: std::min(a, b) is b < a ? b : a, std::max(a, b) is a < b ? b : a), so
// every lane is the scalar value bit for bit. Included by view_trace_simd.cpp after the lane
// operations.

/// std::min(a, b) and std::max(a, b), lane by lane.
BT_LANES_INLINE D std_min(D a, D b) { return seld(ltd(b, a), b, a); }
BT_LANES_INLINE D std_max(D a, D b) { return seld(ltd(a, b), b, a); }

/// std::clamp(v, 0, last) of whole numbers, lane by lane.
BT_LANES_INLINE D clamp_cell(D v, D last) {
    return seld(ltd(v, set1d(0.0)), set1d(0.0), seld(ltd(last, v), last, v));
}

/// The span between the window's two sides along one axis (o: origin, d: direction, inv_d:
/// 1 / d), as RaySetup::clip's slab: narrows [t0, t1] where d != 0; where d == 0 the rays stay
/// in the window only if `inside` (o in [0, w)), and `enter` loses them otherwise.
BT_LANES_INLINE void clip_slab(D o, D d, D inv_d, D w, bool inside, D& t0, D& t1, M& enter) {
    const D zero = set1d(0.0);
    const M moving = mandnot(eqd(d, zero), enter);
    const D a = muld(subd(zero, o), inv_d);
    const D b = muld(subd(w, o), inv_d);
    t0 = seld(moving, std_max(t0, std_min(a, b)), t0);
    t1 = seld(moving, std_min(t1, std_max(a, b)), t1);
    if (!inside) {
        enter = moving;
    }
}

/// RaySetup::clip of the lanes' rays: their span and start cell into out at [k, k + kLanes).
/// Returns the bits of the lanes whose rays enter the loaded heights.
BT_LANES_INLINE int clip_lanes(const ClipFrame& c, D dx, D dy, D dz, D inv_dx, D inv_dy, D inv_dz,
                               RowDirections& out, int k) {
    if (c.zmax == -kInf) {
        return 0;
    }
    const D zero = set1d(0.0), w = set1d(c.w), zmax = set1d(c.zmax);
    const D ox = set1d(c.ox), oy = set1d(c.oy), oz = set1d(c.oz);
    D t0 = zero, t1 = set1d(kInf);
    M enter = mask_of_bits((1 << kLanes) - 1);
    clip_slab(ox, dx, inv_dx, w, c.ox >= 0 && c.ox < c.w, t0, t1, enter);
    clip_slab(oy, dy, inv_dy, w, c.oy >= 0 && c.oy < c.w, t0, t1, enter);
    // (zmax - oz) * inv_dz and floor_dz * inv_dz are used only where dz has the sign that makes
    // them the clip's (a level ray's +-inf or NaN is never selected).
    const D to_top = muld(subd(zmax, oz), inv_dz);
    const M down = ltd(dz, zero), up = ltd(zero, dz);
    if (c.oz > c.zmax) {
        enter = mand(enter, down);
        t0 = std_max(t0, to_top);
    }
    const D limit = seld(up, to_top, muld(set1d(c.floor_dz), inv_dz));
    t1 = seld(mor(up, down), std_min(t1, limit), t1);
    enter = mand(enter, led(t0, t1));
    // floor_to_int(o + d * t0) clamped to the window: whole numbers well inside +-2^53 where
    // the ray enters (the position lies in the window up to a rounding), so exact as doubles.
    const D last = set1d(c.last);
    store(out.t_min + k, t0);
    store(out.t_max + k, t1);
    store(out.gx + k, clamp_cell(floord(addd(ox, muld(dx, t0))), last));
    store(out.gy + k, clamp_cell(floord(addd(oy, muld(dy, t0))), last));
    return bits(enter);
}

BT_LANES void directions(const DirectionFrame& f, const ClipFrame& c, const double* u, double v,
                         int count, RowDirections& out) {
    alignas(64) double uu[kRowDirections] = {};
    for (int i = 0; i < count; ++i) {
        uu[i] = u[i];
    }
    const D vv = set1d(v);
    const D one = set1d(1.0), zero = set1d(0.0), inf = set1d(kInf), per_cell = set1d(f.per_cell);
    int enter = 0;
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
        const D inv_dx = seld(eqd(dx, zero), inf, divd(one, dx));
        const D inv_dy = seld(eqd(dy, zero), inf, divd(one, dy));
        const D inv_dz = divd(one, dz);
        store(out.dx + k, dx);
        store(out.dy + k, dy);
        store(out.dz + k, dz);
        store(out.inv_dx + k, inv_dx);
        store(out.inv_dy + k, inv_dy);
        store(out.inv_dz + k, inv_dz);
        enter |= clip_lanes(c, dx, dy, dz, inv_dx, inv_dy, inv_dz, out, k) << k;
    }
    out.enter = enter & ((1 << count) - 1);
}

/// axis_exit (view_beam.hpp) of cells c (whole numbers as doubles) along one axis: off is 1
/// where the axis' sign is positive, else 0.
BT_LANES_INLINE D exit_of(D c, D off, D o, D inv_d) { return muld(subd(addd(c, off), o), inv_d); }

/// axis_cell_at (view_beam.hpp) of the lanes of `on` along one axis (origin o, direction d):
/// the cell the walk from `start` is in at t, and in `entry` the distance it entered it (-inf
/// for `start`). The other lanes (and those with d == 0) keep `start`.
BT_LANES_INLINE D cell_at(M on, D start, D o, D d, D inv_d, D cells, D t, D& entry) {
    const D zero = set1d(0.0), one = set1d(1.0), minus = set1d(-1.0);
    const M neg = ltd(d, zero);
    const D sd = seld(neg, minus, one), off = seld(neg, zero, one);
    const M moving = mandnot(eqd(d, zero), on);
    D c = floord(addd(o, muld(d, t)));
    c = seld(ltd(c, minus), minus, seld(ltd(cells, c), cells, c));  // std::clamp(c, -1, cells)
    // Not behind the start: (c - start) * sd < 0 keeps the start.
    const M behind = mor(mand(neg, ltd(start, c)), mandnot(neg, ltd(c, start)));
    c = seld(mandnot(behind, moving), c, start);
    for (;;) {
        const M back =
            mand(mandnot(eqd(c, start), moving), ltd(t, exit_of(subd(c, sd), off, o, inv_d)));
        if (bits(back) == 0) {
            break;
        }
        c = seld(back, subd(c, sd), c);
    }
    for (;;) {
        const M ahead = mand(moving, led(exit_of(c, off, o, inv_d), t));
        if (bits(ahead) == 0) {
            break;
        }
        c = seld(ahead, addd(c, sd), c);
    }
    entry = seld(mandnot(eqd(c, start), moving), exit_of(subd(c, sd), off, o, inv_d),
                 set1d(-kInf));
    return c;
}

BT_LANES int start_rays(const ClipFrame& cf, double t_start, std::int64_t window,
                        RowDirections& r) {
    const D t = set1d(t_start), ox = set1d(cf.ox), oy = set1d(cf.oy);
    const D cells = set1d(static_cast<double>(window)), zero = set1d(0.0);
    int go_on = 0;
    for (int k = 0; k < kRowDirections; k += kLanes) {
        const M enter = mask_of_bits((r.enter >> k) & ((1 << kLanes) - 1));
        const D t_min = load(r.t_min + k), gx = load(r.gx + k), gy = load(r.gy + k);
        // Rays whose start lies before t move on to it; those that end before it are lost.
        const M moved = mand(enter, ltd(t_min, t));
        const M ends = mand(moved, ged(t, load(r.t_max + k)));
        const M walk = mandnot(ends, moved);
        D ex, ey;
        const D cx = cell_at(walk, gx, ox, load(r.dx + k), load(r.inv_dx + k), cells, t, ex);
        const D cy = cell_at(walk, gy, oy, load(r.dy + k), load(r.inv_dy + k), cells, t, ey);
        const M outside =
            mor(mor(ltd(cx, zero), ltd(cy, zero)), mor(led(cells, cx), led(cells, cy)));
        const M lost = mor(ends, mand(walk, outside));
        const M jumped = mandnot(mand(eqd(cx, gx), eqd(cy, gy)), mandnot(lost, walk));
        // The later of the two entries (through x on a tie), as start_ray_at.
        store(r.entered + k, seld(jumped, seld(ged(ex, ey), zero, set1d(1.0)), set1d(-1.0)));
        store(r.t_min + k, seld(jumped, std_max(ex, ey), t_min));
        store(r.gx + k, seld(jumped, cx, gx));
        store(r.gy + k, seld(jumped, cy, gy));
        go_on |= bits(mandnot(lost, enter)) << k;
    }
    return go_on;
}
