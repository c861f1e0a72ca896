// shade_hit (grid_ray.hpp) of a batch of hits without height stacks in SIMD lanes: the same IEEE
// operations in the same order (muld never fuses with addd), std::exp one lane at a time, and
// the choices of std::min, std::max and std::clamp (std_min, std_max of view_lanes_setup.inl),
// so every depth and colour byte is shade_hit's. Included by view_trace_simd.cpp after the lane
// operations and view_lanes_setup.inl.

/// x / (2 * cell size) as ExactDivisor works it out.
BT_LANES_INLINE D per_two_cells(const ShadeFrame& f, D x) {
    return f.per_two_product ? muld(x, set1d(f.per_two_inv)) : divd(x, set1d(f.per_two));
}

/// shade_hit's at(v) without stacks: the cell's own height h where the neighbour is empty.
BT_LANES_INLINE D neighbour_or(D v, D h) {
    return seld(eqd(v, set1d(static_cast<double>(kEmptyHeight))), h, v);
}

/// The light of shade_hit (0.35 + 0.65 * max(0, n . sun)) of the lanes' hits at [k, k +
/// kLanes): the top's normal from the neighbours' central differences, else the face the walk
/// entered through.
BT_LANES_INLINE D shade_light(const ShadeFrame& f, const ShadeBatch& b, int k, D h, M top) {
    const D zero = set1d(0.0), one = set1d(1.0), minus = set1d(-1.0);
    const D gx = per_two_cells(
        f, subd(neighbour_or(load(b.nb[0] + k), h), neighbour_or(load(b.nb[1] + k), h)));
    const D gy = per_two_cells(
        f, subd(neighbour_or(load(b.nb[2] + k), h), neighbour_or(load(b.nb[3] + k), h)));
    // normalize(Vec3d(-gx, -gy, 1.0)): a * (1 / sqrt((ax * ax + ay * ay) + 1 * 1)).
    const D ax = negd(gx), ay = negd(gy);
    const D len = sqrtd(addd(addd(muld(ax, ax), muld(ay, ay)), muld(one, one)));
    const D inv = divd(one, len);
    // The sides: (-sx, 0, 0) through an x face (entered 0), (0, -sy, 0) through a y face.
    const M x_face = eqd(load(b.entered + k), zero);
    const D nx = seld(top, muld(ax, inv), seld(x_face, muld(load(b.sx + k), minus), zero));
    const D ny = seld(top, muld(ay, inv), seld(x_face, zero, muld(load(b.sy + k), minus)));
    const D nz = seld(top, muld(one, inv), zero);
    const D d =
        addd(addd(muld(nx, set1d(f.sun_x)), muld(ny, set1d(f.sun_y))), muld(nz, set1d(f.sun_z)));
    return addd(set1d(0.35), muld(set1d(0.65), std_max(zero, d)));
}

/// The distance to the hit and its light, and the fog's exponent -t / fog_distance (into
/// nb[0]), of the lanes' hits at [k, k + kLanes).
BT_LANES_INLINE void shade_lit(const ShadeFrame& f, ShadeBatch& b, int k) {
    const D zero = set1d(0.0);
    const D h = load(b.h + k), t_in = load(b.t_in + k), dz = load(b.dz + k);
    // Going down, the top's plane where it lies past t_in (clipped to t_out), else t_in.
    const D t_top = divd(subd(h, set1d(f.oz)), dz);
    const M on_top = mand(ltd(dz, zero), ltd(t_in, t_top));
    const D t = seld(on_top, std_min(t_top, load(b.t_out + k)), t_in);
    store_floats(b.depth + k, t);
    if (f.shading) {
        const M top = mor(on_top, ltd(load(b.entered + k), zero));
        const D light = shade_light(f, b, k, h, top);
        for (auto& c : b.c) {
            store(c + k, muld(load(c + k), light));
        }
    }
    if (f.fog_distance > 0) {
        store(b.nb[0] + k, divd(negd(t), set1d(f.fog_distance)));
    }
}

/// The fog's blend (where on), std::clamp to [0, 255] and round_byte of the lanes' colours at
/// [k, k + kLanes) into rgb.
BT_LANES_INLINE void shade_bytes(const ShadeFrame& f, ShadeBatch& b, int k) {
    const D zero = set1d(0.0), one = set1d(1.0), top = set1d(255.0), half = set1d(0.5);
    D fog = zero, clear = one;
    if (f.fog_distance > 0) {
        fog = subd(one, load(b.nb[0] + k));  // f = 1 - exp(-t / fog_distance)
        clear = subd(one, fog);
    }
    for (int i = 0; i < 3; ++i) {
        D c = load(b.c[i] + k);
        if (f.fog_distance > 0) {
            c = addd(muld(c, clear), muld(set1d(f.sky[i]), fog));
        }
        c = seld(ltd(c, zero), zero, seld(ltd(top, c), top, c));
        const D whole = truncd(c);
        store_ints(b.rgb[i] + k, addd(whole, seld(ged(subd(c, whole), half), one, zero)));
    }
}

BT_LANES void shade(const ShadeFrame& f, ShadeBatch& b, int count) {
    for (int k = 0; k < count; k += kLanes) {
        shade_lit(f, b, k);
    }
    if (f.fog_distance > 0) {
        for (int k = 0; k < count; ++k) {
            b.nb[0][k] = std::exp(b.nb[0][k]);
        }
    }
    for (int k = 0; k < count; k += kLanes) {
        shade_bytes(f, b, k);
    }
}
