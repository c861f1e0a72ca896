// The hierarchical traversal of trace_octant (view_renderer.cpp) for kLanes rays at once, one
// ray per lane: descending or stepping is a per-lane select, and a lane takes the next ray as
// soon as its ray ends. Written once against the lane operations of view_lanes_avx2x2.inl
// (AVX2: eight lanes in pairs of registers) or view_lanes_avx512.inl, which
// view_trace_simd.cpp includes first in the same namespace.

/// The lanes' rays and walks, one value per field. A new ray enters its lane by masked
/// broadcasts (put): stored one field at a time into arrays instead, the next turn's vector
/// loads of those arrays waited for the stores (a store-forwarding stall every turn a ray ended).
/// The signs of dx and dy are not fields: the turn takes them from dx and dy (a ray's sx and sy
/// are RaySetup's, -1 where d < 0, else 1), two fewer values to keep and put.
struct Lanes {
    D ox, oy, oz, dx, dy, dz, inv_dx, inv_dy, t_max, t;
    I cx, cy, level, entered;
    I streak;  ///< turns since the walk last descended

    BT_LANES_INLINE void start(int j, const GridRay& r, int top) {
        ox = put(ox, j, r.ox);
        oy = put(oy, j, r.oy);
        oz = put(oz, j, r.oz);
        dx = put(dx, j, r.dx);
        dy = put(dy, j, r.dy);
        dz = put(dz, j, r.dz);
        inv_dx = put(inv_dx, j, r.inv_dx);
        inv_dy = put(inv_dy, j, r.inv_dy);
        t_max = put(t_max, j, r.t_max);
        t = put(t, j, r.t_min);
        const int l = r.level < 0 ? top : r.level;
        cx = put(cx, j, r.gx >> l);
        cy = put(cy, j, r.gy >> l);
        level = put(level, j, std::int64_t{l});
        entered = put(entered, j, std::int64_t{r.entered});
        streak = put(streak, j, std::int64_t{0});
    }
    /// A lane with no ray: a harmless state (it is masked out).
    BT_LANES_INLINE void stop(int j) {
        level = put(level, j, std::int64_t{0});
        cx = put(cx, j, std::int64_t{0});
        cy = put(cy, j, std::int64_t{0});
        streak = put(streak, j, std::int64_t{0});
        // One put a field (no loop over the fields' addresses: that kept the whole state in
        // memory, and the turn copied it to other stack slots).
        ox = put(ox, j, 0.0);
        oy = put(oy, j, 0.0);
        oz = put(oz, j, 0.0);
        dz = put(dz, j, 0.0);
        t = put(t, j, 0.0);
        dx = put(dx, j, 1.0);
        dy = put(dy, j, 1.0);
        inv_dx = put(inv_dx, j, 1.0);
        inv_dy = put(inv_dy, j, 1.0);
        t_max = put(t_max, j, 1.0);
    }
};

/// The rays the lanes take in turn, and which ray each lane has (apart from the lanes' vectors,
/// which the compiler then keeps as separate values, not as one object in memory).
struct Feed {
    const GridRay* rays;
    std::size_t count;
    int top;
    std::size_t next = 0;
    int active_bits = 0;  ///< bit j: lane j has a ray
    std::size_t ray[kLanes] = {};
};

/// Lane j takes the next ray of `f` (or stops when none is left).
BT_LANES_INLINE void refill(Lanes& s, int j, Feed& f) {
    if (f.next < f.count) {
        s.start(j, f.rays[f.next], f.top);
        f.ray[j] = f.next++;
        f.active_bits |= 1 << j;
    } else {
        s.stop(j);
        f.active_bits &= ~(1 << j);
    }
}

/// The per-frame constants of the height lookup.
struct Lookup {
    const float* const* address;
    I n, n2, top1, shift, pyramid_base, pyramid_shift0, one;
};

/// The height lookup's constants of `table`.
BT_LANES_INLINE Lookup lookup_of(const LevelTable& table) {
    const int top = table.section_top();
    const auto n = static_cast<std::int64_t>(table.sections_per_side());
    Lookup p{};
    p.address = table.address_table();
    p.n = set1(n);
    p.n2 = set1(n * n);
    p.top1 = set1(top + 1);
    p.shift = set1(table.finest_shift());
    p.pyramid_base = set1(static_cast<std::int64_t>(table.pyramid_slot(0)));
    p.pyramid_shift0 = set1(table.root() > top ? table.row_shift(0) : 0);
    p.one = set1(1);
    return p;
}

/// LevelTable::height(level, x, y) for the lanes of `enabled`.
BT_LANES_INLINE D heights(const Lookup& p, I level, I x, I y, M enabled) {
    // The sections' levels: slot (y >> sh) * n + (x >> sh), rows of 2^sh cells.
    const I sh = sub(p.shift, level);
    const I slot = add(mul32(srlv(y, sh), p.n), srlv(x, sh));
    const I entry_s = add(mul32(level, p.n2), slot);
    const I m = sub(sllv(p.one, sh), p.one);
    const I off_s = add(sllv(band(y, m), sh), band(x, m));
    // The pyramid's levels: one address each, rows of 2^(shift0 - k) cells.
    const I k = sub(level, p.top1);
    const I off_p = add(sllv(y, sub(p.pyramid_shift0, k)), x);
    const M in_sections = gt(p.top1, level);
    return load_heights(p.address, sel(in_sections, entry_s, add(p.pyramid_base, k)),
                        sel(in_sections, off_s, off_p), enabled);
}

/// found[i] of the rays of the lanes of `done` (1 for those of `hit_bits`) and hits[i] of
/// their hits: the lanes' cell (cx, cy), entry t, exit t_end, face and height h.
BT_LANES_INLINE void record(const Feed& feed, int done, int hit_bits, D h, D t_end, D t, I cx, I cy,
                            I entered, GridHit* hits, std::uint8_t* found) {
    alignas(64) double h_lanes[kLanes], t_end_lanes[kLanes], t_lanes[kLanes];
    alignas(64) std::int64_t cx_lanes[kLanes], cy_lanes[kLanes], entered_lanes[kLanes];
    store(h_lanes, h);
    store(t_end_lanes, t_end);
    store(t_lanes, t);
    store(cx_lanes, cx);
    store(cy_lanes, cy);
    store(entered_lanes, entered);
    // Only the lanes that ended, lowest first (a test of every lane mispredicted about once a
    // turn: which lanes end is all but random).
    for (int left = done; left != 0; left &= left - 1) {
        const int j = __builtin_ctz(static_cast<unsigned>(left));
        const std::size_t i = feed.ray[j];
        const bool is_hit = (hit_bits & (1 << j)) != 0;
        found[i] = is_hit ? 1 : 0;
        if (is_hit) {
            GridHit& g = hits[i];
            g.x = cx_lanes[j];
            g.y = cy_lanes[j];
            g.t_in = t_lanes[j];
            g.t_out = t_end_lanes[j];
            g.entered_axis = static_cast<int>(entered_lanes[j]);
            g.h = static_cast<float>(h_lanes[j]);
            g.bottom = false;
        }
    }
}

/// The climb of the walk's step into the pyramid's levels, for the lanes of `climbing` (those
/// whose step to (acx, acy) of level alevel, at least the sections' top, was not a potential
/// hit): while the step left its parent cell (along the axes of step_x and step_y, climb_x and
/// climb_y 0 going up the axis, else -1) and the parent is empty, up to it.
[[gnu::noinline]] BT_LANES void climb_pyramid(const Lookup& p, I top_v, I root, M step_x, M step_y,
                                              I climb_x, I climb_y, M climbing, I& acx, I& acy,
                                              I& alevel) {
    const I zero = set1(0), one = set1(1);
    const D empty = set1d(static_cast<double>(kEmptyHeight));
    for (;;) {
        const M cross_x = mand(step_x, eq(band(bxor(acx, climb_x), one), zero));
        const M cross_y = mand(step_y, eq(band(bxor(acy, climb_y), one), zero));
        climbing = mand(mand(climbing, mor(cross_x, cross_y)),
                        mandnot(gt(top_v, alevel), gt(root, alevel)));
        if (bits(climbing) == 0) {
            return;
        }
        const I up_level = add(alevel, one);
        const I px2 = srl1(acx), py2 = srl1(acy);
        climbing = mand(climbing, eqd(heights(p, up_level, px2, py2, climbing), empty));
        alevel = sel(climbing, up_level, alevel);
        acx = sel(climbing, px2, acx);
        acy = sel(climbing, py2, acy);
    }
}

BT_LANES void trace(const LevelTable& table, const GridRay* rays, std::size_t count, GridHit* hits,
                    std::uint8_t* found) {
    const int top = table.section_top();
    const I zero = set1(0);
    const I one = set1(1);
    const Lookup p = lookup_of(table);
    const I top_v = set1(top);
    const I root = set1(table.root());
    const I window = set1(table.cells(0));
    const D zerod = set1d(0.0);

    Lanes s{};
    s.ox = s.oy = s.oz = s.dx = s.dy = s.dz = s.inv_dx = s.inv_dy = s.t_max = s.t = zerod;
    s.cx = s.cy = s.level = s.entered = zero;
    s.streak = zero;
    Feed feed{rays, count, top};
    for (int j = 0; j < kLanes; ++j) {
        refill(s, j, feed);
    }
    M active = mask_of_bits(feed.active_bits);
    while (feed.active_bits != 0) {
        const D ox = s.ox, oy = s.oy, oz = s.oz;
        const D dx = s.dx, dy = s.dy, dz = s.dz;
        const D t = s.t, t_max = s.t_max;
        const I level = s.level, cx = s.cx, cy = s.cy;
        // The climb's offset (-1 going down the axis, else 0) and the far side's (0 or 1), from
        // the signs of dx and dy (a ray's sx and sy are -1 where d < 0, else 1: RaySetup's).
        const I climb_x = negative(dx), climb_y = negative(dy);
        const I off_x = add(climb_x, one), off_y = add(climb_y, one);

        // The cell's exits and the ray's height over it, as trace_octant.
        const D bx = to_double(sllv(add(cx, off_x), level));
        const D by = to_double(sllv(add(cy, off_y), level));
        const D tx = muld(subd(bx, ox), s.inv_dx);
        const D ty = muld(subd(by, oy), s.inv_dy);
        const D t_out = mind(ty, tx);        // std::min(tx, ty)
        const D t_end = mind(t_max, t_out);  // std::min(t_out, t_max)
        const D h = heights(p, level, cx, cy, active);
        const D z = addd(oz, muld(dz, seld(ltd(dz, zerod), t_end, t)));
        const M below = mand(led(z, h), active);
        const M hit = mand(below, eq(level, zero));

        // Descend: the child under the ray at t.
        const I down_level = sub(level, one);
        const D px = addd(ox, muld(dx, t));
        const D py = addd(oy, muld(dy, t));
        const I cx2 = add(cx, cx), cy2 = add(cy, cy);
        const I dcx = add(cx2, keep(ged(px, to_double(sllv(add(cx2, one), down_level))), one));
        const I dcy = add(cy2, keep(ged(py, to_double(sllv(add(cy2, one), down_level))), one));

        // Step to the next cell. Past t_max, or out of the window (ceil(window cells /
        // 2^level) cells per side, as LevelTable::cells: the cell's first column at level 0,
        // as an unsigned number, below the window's cells), the ray ends.
        const M step_x = led(tx, ty);
        const M step_y = led(ty, tx);
        I acx = add(cx, keep(step_x, bor(climb_x, one)));
        I acy = add(cy, keep(step_y, bor(climb_y, one)));
        const M inside =
            mand(mand(ult(sllv(acx, level), window), ult(sllv(acy, level), window)), active);
        const M out = mor(ged(t_out, t_max), mandnot(inside, active));
        const M miss = mandnot(below, mand(active, out));
        // Climb while the step left the parent: within the sections' levels at most streak / 2
        // levels, the turns since the walk last descended (near the surface a walk that climbs
        // as far as it may descends right back: of the 15.6 M turns of the benchmark's frame
        // 7.6 M were descents; 13.0 M turns in all this way)...
        const I streak = s.streak;
        const I kx = keep(step_x, trailing_zeros(bxor(acx, climb_x)));
        const I ky = keep(step_y, trailing_zeros(bxor(acy, climb_y)));
        const I k = min64(min64(max64(kx, ky), max64(sub(top_v, level), zero)), srl1(streak));
        I alevel = add(level, k);
        acx = srlv(acx, k);
        acy = srlv(acy, k);
        // ... and into the pyramid only while its cell there is empty (seldom: out of line).
        const M climbing =
            mand(mandnot(mor(below, out), active), mandnot(gt(top_v, alevel), gt(root, alevel)));
        if (bits(climbing) != 0) {
            // Copies: the references' objects live in memory, acx, acy and alevel in registers.
            I x = acx, y = acy, l = alevel;
            climb_pyramid(p, top_v, root, step_x, step_y, climb_x, climb_y, climbing, x, y, l);
            acx = x;
            acy = y;
            alevel = l;
        }

        const int hit_bits = bits(hit);
        const int done = hit_bits | bits(miss);
        if (done != 0) {
            record(feed, done, hit_bits, h, t_end, t, cx, cy, s.entered, hits, found);
        }
        s.streak = sel(below, zero, add(streak, one));
        s.cx = sel(below, dcx, acx);
        s.cy = sel(below, dcy, acy);
        s.level = sel(below, down_level, alevel);
        s.t = seld(below, t, t_out);
        s.entered = sel(below, s.entered, sel(step_x, zero, one));
        for (int left = done; left != 0; left &= left - 1) {
            refill(s, __builtin_ctz(static_cast<unsigned>(left)), feed);
        }
        if (done != 0) {
            active = mask_of_bits(feed.active_bits);
        }
    }
}
