// The packet kernel, included by packet_trace.cpp once per instruction set inside a namespace
// that defines kLanes, the vector types vf (float), vi (int32, what comparisons give) and vu
// (uint32), lane_bits(vi) (one bit per lane), lanes_of(mask) (all bits set in its lanes),
// lanes_to_float(x) (kLanes doubles in float), BT_PK
// (inline helpers) and BT_PK_ENTRY (the entry point), all compiled for that instruction set. Every
// float expression below is the scalar one of trace_ray.hpp / ray_triangle.hpp / queries.hpp in
// lanes, operand for operand.

using Mask = std::uint32_t;
constexpr Mask kAllLanes = kLanes == 32 ? ~Mask{0} : (Mask{1} << kLanes) - 1;

BT_PK vf splat(float s) {
    vf r{};
    for (int l = 0; l < kLanes; ++l) {
        r[l] = s;
    }
    return r;
}

BT_PK vu splat_u(std::uint32_t s) {
    vu r{};
    for (int l = 0; l < kLanes; ++l) {
        r[l] = s;
    }
    return r;
}

BT_PK vf vabs(vf x) {
    return reinterpret_cast<vf>(reinterpret_cast<vu>(x) & splat_u(0x7fffffffu));
}

/// One packet: the rays of TraceRay, lane by lane, and each lane's NearestVisitor state.
struct Packet {
    vf o[3];    ///< origin by axis
    vf d[3];    ///< direction by axis
    vf inv[3];  ///< 1 / direction by axis (slab_inverse)
    vf ok[3];   ///< origin in the watertight order (kx, ky, kz)
    vf sx, sy, sz;
    vf tmin;
    vf limit;  ///< the nearest hit so far and a few ulps (NearestVisitor's limit)
    vf best_t, best_u, best_v;
    vu best_face;
    std::size_t kx = 0, ky = 1, kz = 2;
    Mask active = 0;
};

/// Rays in float, structure of arrays, as make_box_ray converts them (a stage of a batch).
struct StageRays {
    static constexpr std::size_t kRays = 1024;
    static constexpr std::size_t kRoom = kRays + kLanes;  ///< a packet's loads may pass the end
    float o[3][kRoom], d[3][kRoom], tmin[kRoom], tmax[kRoom];
};

/// The lanes of `active` from x[0..kLanes); the others copy lane 0.
BT_PK vf load_lanes(const float* x, Mask active) {
    vf v;
    __builtin_memcpy(&v, x, sizeof v);
    return active == kAllLanes ? v : (lanes_of(active) ? v : splat(x[0]));
}

/// Lanes [0, n) from rays [at, at + n) of `st`, which share the watertight axis order (kz and
/// whether kx, ky swap: group `group`); lanes past n copy ray `at` and stay inactive. Every
/// division is make_trace_ray's, in lanes (IEEE division rounds alike in both).
BT_PK void load_packet(Packet& p, const StageRays& st, std::size_t at, int n, int group) {
    p.active = n >= kLanes ? kAllLanes : (Mask{1} << n) - 1;
    p.kz = static_cast<std::size_t>(group / 2);
    p.kx = (p.kz + 1) % 3;
    p.ky = (p.kx + 1) % 3;
    if (group % 2 != 0) {
        std::swap(p.kx, p.ky);
    }
    for (std::size_t a = 0; a < 3; ++a) {
        p.o[a] = load_lanes(&st.o[a][at], p.active);
        p.d[a] = load_lanes(&st.d[a][at], p.active);
        p.inv[a] = 1.0f / (p.d[a] + 0.0f);
    }
    p.ok[0] = p.o[p.kx];
    p.ok[1] = p.o[p.ky];
    p.ok[2] = p.o[p.kz];
    const vf dz = p.d[p.kz];
    p.sx = p.d[p.kx] / dz;
    p.sy = p.d[p.ky] / dz;
    p.sz = 1.0f / dz;
    p.tmin = load_lanes(&st.tmin[at], p.active);
    p.best_t = load_lanes(&st.tmax[at], p.active);
    p.limit = p.best_t * kNearestRoom;
    p.best_u = p.best_v = splat(0.0f);
    p.best_face = splat_u(kNoFace);
}

/// slab_interval of every lane against its own limit: the lanes that enter the box, and their
/// padded entry distances.
BT_PK Mask slab_lanes(const Packet& p, const BvhNode& node, vf& entry) {
    constexpr float kPad = 2.0f * 3.0f * std::numeric_limits<float>::epsilon();
    vf tnear = p.tmin, tfar = p.limit;
    for (int a = 0; a < 3; ++a) {
        const vf t0 = (node.lo[a] - p.o[a]) * p.inv[a];
        const vf t1 = (node.hi[a] - p.o[a]) * p.inv[a];
        const vf n = (t1 < t0) ? t1 : t0;
        const vf f = (t0 > t1) ? t0 : t1;
        tnear = (n > tnear) ? n : tnear;
        const vf fp = (f >= 0.0f) ? f * (1.0f + kPad) : f * (1.0f - kPad);
        tfar = (fp < tfar) ? fp : tfar;
    }
    entry = tnear - vabs(tnear) * kPad;
    return lane_bits(tnear <= tfar);
}

/// The scalar test for lane l (a face exactly on an edge in float: decided in double there).
BT_PK void test_lane(Packet& p, int l, std::uint32_t face, const Vec3f& a, const Vec3f& b,
                     const Vec3f& c) {
    TriangleHit h;
    WatertightRay wt;
    wt.org = Vec3f(p.o[0][l], p.o[1][l], p.o[2][l]);
    wt.kx = static_cast<int>(p.kx);
    wt.ky = static_cast<int>(p.ky);
    wt.kz = static_cast<int>(p.kz);
    wt.sx = p.sx[l];
    wt.sy = p.sy[l];
    wt.sz = p.sz[l];
    if (intersect_watertight(wt, a, b, c, p.tmin[l], p.limit[l], Facing::both, h) &&
        (h.t < p.best_t[l] || (h.t == p.best_t[l] && face < p.best_face[l]))) {
        p.best_t[l] = h.t;
        p.limit[l] = h.t * kNearestRoom;
        p.best_face[l] = face;
        p.best_u[l] = h.u;
        p.best_v[l] = h.v;
    }
}

/// A face's corners, and their coordinates in the watertight order (kx, ky, kz) of the packets
/// that test it (test_face), permuted once for all of them.
struct FaceCorners {
    const Vec3f *a, *b, *c;
    float ak[3], bk[3], ck[3];
};

BT_PK void load_corners(const TriangleMesh& mesh, std::uint32_t face, const Packet& p,
                        FaceCorners& fc) {
    const Face& f = mesh.faces[face];
    fc.a = &mesh.vertices[f[0]];
    fc.b = &mesh.vertices[f[1]];
    fc.c = &mesh.vertices[f[2]];
    const std::size_t k[3] = {p.kx, p.ky, p.kz};
    for (int i = 0; i < 3; ++i) {
        fc.ak[i] = (*fc.a)[k[i]];
        fc.bk[i] = (*fc.b)[k[i]];
        fc.ck[i] = (*fc.c)[k[i]];
    }
}

/// NearestVisitor::visit of face `face` (corners fc, in p's watertight order) in the lanes of
/// `mask`; true if a lane's hit changed.
BT_PK bool test_face(Packet& p, const FaceCorners& fc, std::uint32_t face, Mask mask) {
    const Vec3f& a = *fc.a;
    const Vec3f& b = *fc.b;
    const Vec3f& c = *fc.c;
    const vf Akx = fc.ak[0] - p.ok[0], Aky = fc.ak[1] - p.ok[1], Akz = fc.ak[2] - p.ok[2];
    const vf Bkx = fc.bk[0] - p.ok[0], Bky = fc.bk[1] - p.ok[1], Bkz = fc.bk[2] - p.ok[2];
    const vf Ckx = fc.ck[0] - p.ok[0], Cky = fc.ck[1] - p.ok[1], Ckz = fc.ck[2] - p.ok[2];
    const vf Ax = Akx - p.sx * Akz, Ay = Aky - p.sy * Akz;
    const vf Bx = Bkx - p.sx * Bkz, By = Bky - p.sy * Bkz;
    const vf Cx = Ckx - p.sx * Ckz, Cy = Cky - p.sy * Ckz;
    const vf U = Cx * By - Cy * Bx;
    const vf V = Ax * Cy - Ay * Cx;
    const vf W = Bx * Ay - By * Ax;
    const vi zero = (U == 0.0f) | (V == 0.0f) | (W == 0.0f);
    const vi outside =
        ((U < 0.0f) | (V < 0.0f) | (W < 0.0f)) & ((U > 0.0f) | (V > 0.0f) | (W > 0.0f));
    const vf det = U + V + W;
    const vi front = det > 0.0f;
    const vf Az = p.sz * Akz, Bz = p.sz * Bkz, Cz = p.sz * Ckz;
    const vf T = U * Az + V * Bz + W * Cz;
    const vf lo = p.tmin * det, hi = p.limit * det;
    const vi clipped = front ? ((T < lo) | (T > hi)) : ((T > lo) | (T < hi));
    const Mask edge = lane_bits(zero) & mask;
    const vi maybe = ~outside & (det != 0.0f) & ~clipped & lanes_of(mask & ~edge);
    Mask take = 0;
    if (lane_bits(maybe) != 0) {  // else no lane needs the division
        const vf inv = 1.0f / det;
        const vf t = T * inv;
        const vi better = (t < p.best_t) | ((t == p.best_t) & (face < p.best_face));
        const vi k = maybe & (t >= p.tmin) & (t <= p.limit) & better;
        take = lane_bits(k);
        p.best_t = k ? t : p.best_t;
        p.limit = k ? t * kNearestRoom : p.limit;
        p.best_face = k ? splat_u(face) : p.best_face;
        p.best_u = k ? V * inv : p.best_u;
        p.best_v = k ? W * inv : p.best_v;
    }
    for (Mask m = edge; m != 0; m &= m - 1) {
        test_lane(p, std::countr_zero(m), face, a, b, c);
    }
    return (take | edge) != 0;
}

BT_PK bool test_face(Packet& p, const TriangleMesh& mesh, std::uint32_t face, Mask mask) {
    FaceCorners fc;
    load_corners(mesh, face, p, fc);
    return test_face(p, fc, face, mask);
}
/// The lanes of `mask` that may still hold a nearer hit than their limit at `entry`.
BT_PK Mask still_open(const Packet& p, const vf& entry, Mask mask) {
    return mask & lane_bits(entry <= p.limit);
}

/// walk_bvh for the packet: a node is entered by the lanes whose slab test passes it; the child
/// that most of the lanes entering both reach first is taken first.
BT_PK void walk_packet(Packet& p, const Bvh& bvh, const TriangleMesh& mesh) {
    struct Entry {
        vf entry;
        std::uint32_t node;
        Mask mask;
    };
    Entry stack[128];
    int sp = 0;
    const BvhNode* nodes = bvh.nodes.data();
    vf entry;
    Mask mask = slab_lanes(p, nodes[0], entry) & p.active;
    std::uint32_t index = 0;
    while (mask != 0) {
        const BvhNode& node = nodes[index];
        if (node.is_leaf()) {
            for (std::uint32_t k = node.index; k < node.index + node.count; ++k) {
                test_face(p, mesh, bvh.prim_ids[k], mask);
            }
        } else {
            const std::uint32_t li = node.index, ri = node.index + 1;
            vf el, er;
            const Mask ml = slab_lanes(p, nodes[li], el) & mask;
            const Mask mr = slab_lanes(p, nodes[ri], er) & mask;
            if (ml != 0 && mr != 0) {
                // Lanes in both: most of them go first; else the child with more lanes.
                const Mask both = ml & mr;
                const bool left =
                    both != 0 ? 2 * std::popcount(lane_bits(el <= er) & both) >= std::popcount(both)
                              : std::popcount(ml) >= std::popcount(mr);
                if (left) {
                    stack[sp++] = {er, ri, mr};
                    index = li;
                    mask = ml;
                } else {
                    stack[sp++] = {el, li, ml};
                    index = ri;
                    mask = mr;
                }
                continue;
            }
            if ((ml | mr) != 0) {
                index = ml != 0 ? li : ri;
                mask = ml | mr;
                continue;
            }
        }
        mask = 0;
        while (sp > 0 && mask == 0) {
            const Entry& e = stack[--sp];
            mask = still_open(p, e.entry, e.mask);
            index = e.node;
        }
    }
}

/// Interval culling (Wald, Boulos & Shirley 2007, "Ray tracing deformable scenes using dynamic
/// bounding volume hierarchies"): the packet's rays bounded together, axis by axis, by the least
/// and greatest origin and inverse direction of its active lanes. A node is skipped only when
/// the bounds show that the slab test of slab_lanes fails in every active lane: float rounding
/// is monotone, so (c - o) * inv over the lanes lies between the same expression's values at
/// the bounds' corners, and the padding, the entry's margin and the limits are monotone too.
/// At a leaf the packet enters, the lanes whose own slab test passes it test its faces; the hits
/// stay the single-ray walk's, since each lane still tests every face its own walk would (see
/// packet_trace.hpp).
using v4 = float __attribute__((vector_size(16)));
using v4i = std::int32_t __attribute__((vector_size(16)));
using v8 = float __attribute__((vector_size(32)));
using v8i = std::int32_t __attribute__((vector_size(32)));

BT_PK v8 twice(v4 x) {
    return __builtin_shufflevector(x, x, 0, 1, 2, 3, 0, 1, 2, 3);
}

BT_PK v8i twice(v4i x) {
    return __builtin_shufflevector(x, x, 0, 1, 2, 3, 0, 1, 2, 3);
}

struct Frustum {
    v4 near_org, far_org;  ///< by axis: the origin bound the near (far) plane is measured from
    v4 inv_lo, inv_hi;     ///< least and greatest inverse direction (0 on free axes)
    v4 org_lo, org_hi;     ///< least and greatest origin
    v4i near_hi;           ///< the near plane is the box's hi (the lanes move down the axis)
    v4i free;              ///< no bound from the slabs on this axis (and in lane 3)
    v4i still;             ///< no lane moves along this axis: only an origin in the slab enters
    // Mixed axes (lanes moving up and down it, a beam about a plane of the axis; free to the
    // code above): the near (far) bound is the least (greatest) of the up lanes' (near_org and
    // far_org, inv_lo, inv_hi: their origins and inverses), the down lanes' (neg_near_org,
    // neg_far_org, ninv_lo, ninv_hi) and the still lanes'.
    v4 neg_near_org, neg_far_org, ninv_lo, ninv_hi;
    v4i mixed, has_pos, has_neg, has_still;
    float tmin = 0;   ///< least tmin of the active lanes
    float limit = 0;  ///< greatest limit of the active lanes
    // The fields above twice over (a node's two children tested at once), made by make_frustum.
    v8 near_org2, far_org2, inv_lo2, inv_hi2, org_lo2, org_hi2;
    v8 neg_near_org2, neg_far_org2, ninv_lo2, ninv_hi2;
    v8i near_hi2, free2, still2, mixed2, has_pos2, has_neg2, has_still2;
};

/// The most rays (whole beams of sub-rays) that walk the tree as one frustum (trace_beams), and
/// the packets they make. The airborne survey's 19-sub-ray beams: one beam a walk took 1.0x the
/// sorted packets' time, 32 rays 1.1x, 64 0.6x, 128 and 256 0.55x, 512 0.6x. Since a leaf's
/// faces are culled by the frustum (test_leaf_faces), wider walks cost fewer instructions: 256
/// rays 0.91x of 128 (AVX2), 512 0.90x.
constexpr int kWalkRays = 256;
constexpr int kBeamPackets = kWalkRays / kLanes;
/// The most packets a frustum walks with (a beam walk's, or a run's: kRunRays / kLanes).
constexpr int kMaxWalkPackets = kBeamPackets > 8 ? kBeamPackets : 8;

/// Bounds of one axis over the active lanes of packets ps[0, np): which way the lanes move,
/// and the least and greatest origin and inverse direction of all of them or, on a mixed axis,
/// of those moving up the axis (pos) and of those moving down (neg).
struct AxisBounds {
    static constexpr float kInf = std::numeric_limits<float>::infinity();
    bool all_pos = true, all_neg = true, all_still = true, classified = true;
    bool any_pos = false, any_neg = false, any_still = false;
    float olo = kInf, ohi = -kInf, inv_lo = kInf, inv_hi = -kInf;
    float pos_olo = kInf, pos_ohi = -kInf, pos_lo = kInf, pos_hi = -kInf;  ///< up lanes
    float neg_olo = kInf, neg_ohi = -kInf, neg_lo = kInf, neg_hi = -kInf;  ///< down lanes

    BT_PK AxisBounds(const Packet* ps, int np, int a, bool mixed) {
        // Each bound lane by lane over the packets (a NaN lane never taken: +inf or -inf if
        // none) and whether an active lane is NaN or zero (moving neither up, down, nor still:
        // unclassified), then one reduction per bound. With every active lane classified, the
        // least and greatest inverse direction tell the classes (all up: both in (0, inf));
        // the up and down lanes' bounds and which classes occur are made apart (bound_apart)
        // where a mixed axis needs them.
        // A packet's inactive lanes hold its lane 0's ray (load_packet), which is active: they
        // change no bound and no class, so every lane is taken (other values there would only
        // widen the frustum).
        const vf hi0 = splat(kInf), lo0 = splat(-kInf);
        vf o_lo = hi0, o_hi = lo0, i_lo = hi0, i_hi = lo0;
        vi odd = vi{};
        for (int q = 0; q < np; ++q) {
            const Packet& p = ps[q];
            const vf o = p.o[a], inv = p.inv[a];
            odd |= ~((inv < 0.0f) | (inv > 0.0f));
            o_lo = (o < o_lo) ? o : o_lo;
            o_hi = (o > o_hi) ? o : o_hi;
            i_lo = (inv < i_lo) ? inv : i_lo;
            i_hi = (inv > i_hi) ? inv : i_hi;
        }
        classified = lane_bits(odd) == 0;
        olo = lanes_min(o_lo);
        ohi = lanes_max(o_hi);
        const float lo = lanes_min(i_lo), hi = lanes_max(i_hi);
        all_pos = classified && lo > 0.0f && hi < kInf;
        all_neg = classified && hi < 0.0f && lo > -kInf;
        // Still: only infinite lanes; with some of either sign, a finite one may lie between.
        all_still = classified && std::fabs(lo) == kInf && std::fabs(hi) == kInf &&
                    (lo != -kInf || hi != kInf || !any_finite(ps, np, a));
        if (all_pos || all_neg) {
            inv_lo = lo;
            inv_hi = hi;
        } else if (mixed && classified && !all_still) {
            bound_apart(ps, np, a);
        }
    }

    /// Whether an active lane of packets ps[0, np) has a finite inverse direction on axis a.
    BT_PK static bool any_finite(const Packet* ps, int np, int a) {
        Mask finite = 0;
        for (int q = 0; q < np; ++q) {
            finite |= lane_bits(vabs(ps[q].inv[a]) < kInf) & ps[q].active;
        }
        return finite != 0;
    }

    /// The bounds of the up lanes and of the down lanes of axis a, apart.
    BT_PK void bound_apart(const Packet* ps, int np, int a) {
        const vf hi0 = splat(kInf), lo0 = splat(-kInf);
        vf po_lo = hi0, po_hi = lo0, pi_lo = hi0, pi_hi = lo0;
        vf no_lo = hi0, no_hi = lo0, ni_lo = hi0, ni_hi = lo0;
        Mask still = 0;
        for (int q = 0; q < np; ++q) {
            const Packet& p = ps[q];
            const vf o = p.o[a], inv = p.inv[a];
            const vi act = lanes_of(p.active);
            const vi pos = (inv > 0.0f) & (inv < kInf) & act;
            const vi neg = (inv < 0.0f) & (inv > -kInf) & act;
            still |= lane_bits(vabs(inv) == kInf) & p.active;
            po_lo = (pos & (o < po_lo)) ? o : po_lo;
            po_hi = (pos & (o > po_hi)) ? o : po_hi;
            pi_lo = (pos & (inv < pi_lo)) ? inv : pi_lo;
            pi_hi = (pos & (inv > pi_hi)) ? inv : pi_hi;
            no_lo = (neg & (o < no_lo)) ? o : no_lo;
            no_hi = (neg & (o > no_hi)) ? o : no_hi;
            ni_lo = (neg & (inv < ni_lo)) ? inv : ni_lo;
            ni_hi = (neg & (inv > ni_hi)) ? inv : ni_hi;
        }
        pos_olo = lanes_min(po_lo);
        pos_ohi = lanes_max(po_hi);
        pos_lo = lanes_min(pi_lo);
        pos_hi = lanes_max(pi_hi);
        neg_olo = lanes_min(no_lo);
        neg_ohi = lanes_max(no_hi);
        neg_lo = lanes_min(ni_lo);
        neg_hi = lanes_max(ni_hi);
        any_pos = pos_lo < kInf;   // an up lane's inverse is finite
        any_neg = neg_hi > -kInf;  // and so is a down lane's
        any_still = still != 0;
    }
};

/// The least tmin and the greatest limit of the active lanes of packets ps[0, np) that are not
/// NaN (+inf and -inf if none).
BT_PK float beam_tmin(const Packet* ps, int np) {
    vf acc = splat(std::numeric_limits<float>::infinity());
    for (int q = 0; q < np; ++q) {
        acc = (lanes_of(ps[q].active) & (ps[q].tmin < acc)) ? ps[q].tmin : acc;
    }
    return lanes_min(acc);
}

BT_PK float beam_limit(const Packet* ps, int np) {
    vf acc = splat(-std::numeric_limits<float>::infinity());
    for (int q = 0; q < np; ++q) {
        acc = (lanes_of(ps[q].active) & (ps[q].limit > acc)) ? ps[q].limit : acc;
    }
    return lanes_max(acc);
}

/// The mixed axis a (frustum_enters_pair<true>): lanes moving up and down it, or some still.
BT_PK void bound_mixed_axis(const AxisBounds& b, int a, Frustum& fr) {
    fr.mixed[a] = -1;
    fr.has_pos[a] = b.any_pos ? -1 : 0;
    fr.has_neg[a] = b.any_neg ? -1 : 0;
    fr.has_still[a] = b.any_still ? -1 : 0;
    // Moving up, the near plane (lo) is nearest from the greatest origin, the far plane (hi)
    // farthest from the least; moving down, the near plane is hi, the far plane lo.
    fr.near_org[a] = b.any_pos ? b.pos_ohi : 0.0f;
    fr.far_org[a] = b.any_pos ? b.pos_olo : 0.0f;
    fr.inv_lo[a] = b.any_pos ? b.pos_lo : 0.0f;
    fr.inv_hi[a] = b.any_pos ? b.pos_hi : 0.0f;
    fr.neg_near_org[a] = b.any_neg ? b.neg_olo : 0.0f;
    fr.neg_far_org[a] = b.any_neg ? b.neg_ohi : 0.0f;
    fr.ninv_lo[a] = b.any_neg ? b.neg_lo : 0.0f;
    fr.ninv_hi[a] = b.any_neg ? b.neg_hi : 0.0f;
}

/// The bounds of axis a over the active lanes of packets ps[0, np); false if the lanes' inverse
/// directions neither share a sign and are finite nor are all infinite (the axis then bounds
/// nothing), unless `mixed` allows such an axis a near bound of its own (bound_mixed_axis).
BT_PK bool bound_axis(const Packet* ps, int np, int a, bool mixed, Frustum& fr) {
    const AxisBounds b(ps, np, a, mixed);
    fr.org_lo[a] = b.olo;
    fr.org_hi[a] = b.ohi;
    fr.free[a] = -1;
    fr.still[a] = b.all_still ? -1 : 0;
    fr.near_hi[a] = b.all_neg ? -1 : 0;
    fr.inv_lo[a] = fr.inv_hi[a] = 0.0f;
    fr.near_org[a] = fr.far_org[a] = 0.0f;
    if (!b.all_pos && !b.all_neg) {
        if (b.all_still || !mixed || !b.classified) {
            return b.all_still;
        }
        bound_mixed_axis(b, a, fr);
        return true;
    }
    fr.free[a] = 0;
    fr.inv_lo[a] = b.inv_lo;
    fr.inv_hi[a] = b.inv_hi;
    // Moving up the axis, the near plane's (lo - o) * inv is least from the greatest origin and
    // the far plane's greatest from the least; moving down, the other way round.
    fr.near_org[a] = b.all_pos ? b.ohi : b.olo;
    fr.far_org[a] = b.all_pos ? b.olo : b.ohi;
    return true;
}

/// The frustum of packets ps[0, np); false if an axis bounds nothing (the lanes' directions
/// differ in sign or some are zero along it, and `mixed` is false), so that culling by it would
/// visit far too many nodes.
BT_PK bool make_frustum(const Packet* ps, int np, bool mixed, Frustum& fr) {
    fr.near_org = fr.far_org = fr.inv_lo = fr.inv_hi = fr.org_lo = fr.org_hi = v4{};
    fr.neg_near_org = fr.neg_far_org = fr.ninv_lo = fr.ninv_hi = v4{};
    fr.near_hi = fr.still = fr.mixed = fr.has_pos = fr.has_neg = fr.has_still = v4i{};
    fr.free = v4i{-1, -1, -1, -1};
    bool bounded = true;
    for (int a = 0; a < 3; ++a) {
        bounded = bound_axis(ps, np, a, mixed, fr) && bounded;
    }
    fr.tmin = beam_tmin(ps, np);
    fr.limit = beam_limit(ps, np);
    fr.near_org2 = twice(fr.near_org);
    fr.far_org2 = twice(fr.far_org);
    fr.inv_lo2 = twice(fr.inv_lo);
    fr.inv_hi2 = twice(fr.inv_hi);
    fr.org_lo2 = twice(fr.org_lo);
    fr.org_hi2 = twice(fr.org_hi);
    fr.neg_near_org2 = twice(fr.neg_near_org);
    fr.neg_far_org2 = twice(fr.neg_far_org);
    fr.ninv_lo2 = twice(fr.ninv_lo);
    fr.ninv_hi2 = twice(fr.ninv_hi);
    fr.near_hi2 = twice(fr.near_hi);
    fr.free2 = twice(fr.free);
    fr.still2 = twice(fr.still);
    fr.mixed2 = twice(fr.mixed);
    fr.has_pos2 = twice(fr.has_pos);
    fr.has_neg2 = twice(fr.has_neg);
    fr.has_still2 = twice(fr.has_still);
    return bounded;
}

/// Whether some active lane may enter `node` (slab_lanes passes it), and a distance at or below
/// the entry distance of every lane that does.
BT_PK bool frustum_enters(const Frustum& fr, const BvhNode& node, float& entry) {
    constexpr float kPad = 2.0f * 3.0f * std::numeric_limits<float>::epsilon();
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr v4 kInf4{kInf, kInf, kInf, kInf};
    v4 lo, hi;
    __builtin_memcpy(&lo, node.lo, sizeof lo);
    __builtin_memcpy(&hi, node.hi, sizeof hi);
    // Lane 3 holds the node's index and count: zeroed, so no denormal or NaN is computed with.
    constexpr v4i kXyz{-1, -1, -1, 0};
    lo = reinterpret_cast<v4>(reinterpret_cast<v4i>(lo) & kXyz);
    hi = reinterpret_cast<v4>(reinterpret_cast<v4i>(hi) & kXyz);
    const v4 dn = (fr.near_hi ? hi : lo) - fr.near_org;
    const v4 df = (fr.near_hi ? lo : hi) - fr.far_org;
    const v4 n0 = dn * fr.inv_lo, n1 = dn * fr.inv_hi;
    const v4 f0 = df * fr.inv_lo, f1 = df * fr.inv_hi;
    const v4 n = (n1 < n0) ? n1 : n0;
    const v4 f = (f0 > f1) ? f0 : f1;
    const v4 fp = (f >= 0.0f) ? f * (1.0f + kPad) : f * (1.0f - kPad);
    const v4i out = fr.still & ((fr.org_hi < lo) | (fr.org_lo > hi));
    const v4 near = fr.free ? (out ? kInf4 : -kInf4) : n;
    const v4 far = fr.free ? kInf4 : fp;
    float tnear = fr.tmin, tfar = fr.limit;
    for (int a = 0; a < 3; ++a) {
        tnear = near[a] > tnear ? near[a] : tnear;
        tfar = far[a] < tfar ? far[a] : tfar;
    }
    // Twice slab_lanes' margin, so that rounding the product cannot lift it over a lane's.
    entry = tnear - std::fabs(tnear) * (2.0f * kPad);
    return tnear <= tfar;
}

/// The bounds of mixed axes (Mixed: frustum_enters_pair), each lane's near and far distance
/// bounded as in bound_axis (float rounding is monotone): the up lanes' near from lo with their
/// greatest origin and far to hi from their least, the down lanes' the other way round, left
/// out where they only move away from the slab (far below the least tmin: they cannot enter);
/// the still lanes' near -inf unless every origin is outside the slab on one side (then +inf, as
/// slab_lanes gives it), far +inf. Other axes keep `near` and `far`.
BT_PK void mixed_bounds(const Frustum& fr, v8 lo, v8 hi, v8& near, v8& far) {
    constexpr float kPad = 2.0f * 3.0f * std::numeric_limits<float>::epsilon();
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr v8 kInf8{kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf};
    const v8 tmin{fr.tmin, fr.tmin, fr.tmin, fr.tmin, fr.tmin, fr.tmin, fr.tmin, fr.tmin};
    const v8 pn = lo - fr.near_org2, pf = hi - fr.far_org2;
    const v8 mn = hi - fr.neg_near_org2, mf = lo - fr.neg_far_org2;
    const v8 pn0 = pn * fr.inv_lo2, pn1 = pn * fr.inv_hi2;
    const v8 pf0 = pf * fr.inv_lo2, pf1 = pf * fr.inv_hi2;
    const v8 mn0 = mn * fr.ninv_lo2, mn1 = mn * fr.ninv_hi2;
    const v8 mf0 = mf * fr.ninv_lo2, mf1 = mf * fr.ninv_hi2;
    const v8 up_near = (pn1 < pn0) ? pn1 : pn0, down_near = (mn1 < mn0) ? mn1 : mn0;
    v8 up_far = (pf0 > pf1) ? pf0 : pf1, down_far = (mf0 > mf1) ? mf0 : mf1;
    up_far = (up_far >= 0.0f) ? up_far * (1.0f + kPad) : up_far * (1.0f - kPad);
    down_far = (down_far >= 0.0f) ? down_far * (1.0f + kPad) : down_far * (1.0f - kPad);
    const v8i up = fr.has_pos2 & (up_far >= tmin), down = fr.has_neg2 & (down_far >= tmin);
    v8 n = up ? up_near : kInf8;
    v8 f = up ? up_far : -kInf8;
    n = (down & (down_near < n)) ? down_near : n;
    f = (down & (down_far > f)) ? down_far : f;
    const v8 s = ((fr.org_hi2 < lo) | (fr.org_lo2 > hi)) ? kInf8 : -kInf8;
    n = (fr.has_still2 & (s < n)) ? s : n;
    f = fr.has_still2 ? kInf8 : f;
    near = fr.mixed2 ? n : near;
    far = fr.mixed2 ? f : far;
}

/// frustum_enters for the two children of an inner node at once (nodes[0] and nodes[1], 64
/// bytes side by side), the same arithmetic lane for lane: bit 0 if the first may be entered,
/// bit 1 the second. Mixed: the frustum may have mixed axes (mixed_near).
template <bool Mixed = false>
BT_PK unsigned frustum_enters_pair(const Frustum& fr, const BvhNode* nodes, float& e0, float& e1) {
    constexpr float kPad = 2.0f * 3.0f * std::numeric_limits<float>::epsilon();
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr v8 kInf8{kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf};
    v8 a, b;
    __builtin_memcpy(&a, &nodes[0], sizeof a);
    __builtin_memcpy(&b, &nodes[1], sizeof b);
    constexpr v8i kXyz{-1, -1, -1, 0, -1, -1, -1, 0};
    const v8 lo = reinterpret_cast<v8>(
        reinterpret_cast<v8i>(__builtin_shufflevector(a, b, 0, 1, 2, 3, 8, 9, 10, 11)) & kXyz);
    const v8 hi = reinterpret_cast<v8>(
        reinterpret_cast<v8i>(__builtin_shufflevector(a, b, 4, 5, 6, 7, 12, 13, 14, 15)) & kXyz);
    const v8 dn = (fr.near_hi2 ? hi : lo) - fr.near_org2;
    const v8 df = (fr.near_hi2 ? lo : hi) - fr.far_org2;
    const v8 n0 = dn * fr.inv_lo2, n1 = dn * fr.inv_hi2;
    const v8 f0 = df * fr.inv_lo2, f1 = df * fr.inv_hi2;
    const v8 n = (n1 < n0) ? n1 : n0;
    const v8 f = (f0 > f1) ? f0 : f1;
    const v8 fp = (f >= 0.0f) ? f * (1.0f + kPad) : f * (1.0f - kPad);
    const v8i out = fr.still2 & ((fr.org_hi2 < lo) | (fr.org_lo2 > hi));
    v8 near = fr.free2 ? (out ? kInf8 : -kInf8) : n;
    v8 far = fr.free2 ? kInf8 : fp;
    if constexpr (Mixed) {
        mixed_bounds(fr, lo, hi, near, far);
    }
    // Greatest near and least far of each half (lane 3 and 7: -inf and +inf).
    v8 sn = __builtin_shufflevector(near, near, 1, 0, 3, 2, 5, 4, 7, 6);
    v8 sf = __builtin_shufflevector(far, far, 1, 0, 3, 2, 5, 4, 7, 6);
    near = (sn > near) ? sn : near;
    far = (sf < far) ? sf : far;
    sn = __builtin_shufflevector(near, near, 2, 3, 0, 1, 6, 7, 4, 5);
    sf = __builtin_shufflevector(far, far, 2, 3, 0, 1, 6, 7, 4, 5);
    near = (sn > near) ? sn : near;
    far = (sf < far) ? sf : far;
    float tn0 = near[0] > fr.tmin ? near[0] : fr.tmin;
    float tn1 = near[4] > fr.tmin ? near[4] : fr.tmin;
    const float tf0 = far[0] < fr.limit ? far[0] : fr.limit;
    const float tf1 = far[4] < fr.limit ? far[4] : fr.limit;
    e0 = tn0 - std::fabs(tn0) * (2.0f * kPad);
    e1 = tn1 - std::fabs(tn1) * (2.0f * kPad);
    return (tn0 <= tf0 ? 1u : 0u) | (tn1 <= tf1 ? 2u : 0u);
}

/// The lanes of packet p that enter leaf `node` (walk_packet's mask) test its faces; true if a
/// lane's hit changed. A leaf that the frustum reaches but no lane does costs one box test.
BT_PK bool test_leaf(Packet& p, const BvhNode& node, const Bvh& bvh, const TriangleMesh& mesh) {
    vf unused;
    const Mask lanes = slab_lanes(p, node, unused) & p.active;
    bool changed = false;
    for (std::uint32_t k = node.index; lanes != 0 && k < node.index + node.count; ++k) {
        changed = test_face(p, mesh, bvh.prim_ids[k], lanes) || changed;
    }
    return changed;
}

/// The box of a face (its corners fc) as a BvhNode's bounds (index and count 0): the box its
/// leaf was built from (Aabb, as TriangleMesh::triangle_bounds makes it), grown on each axis by
/// 2^-20 of the axis' greatest magnitude, a margin beyond the one the leaf boxes need.
BT_PK void face_box(const FaceCorners& fc, BvhNode& box) {
    Aabb b;
    b.extend(*fc.a);
    b.extend(*fc.b);
    b.extend(*fc.c);
    for (int k = 0; k < 3; ++k) {
        const float grow = std::max(std::fabs(b.lo[k]), std::fabs(b.hi[k])) * 0x1p-20f;
        box.lo[k] = b.lo[k] - grow;
        box.hi[k] = b.hi[k] + grow;
    }
    box.index = 0;
    box.count = 0;
}

/// The faces of leaf `node` for packets ps[0, np) walking as frustum `fr` (np > 1): each pair
/// of faces is tested against the frustum first (frustum_enters_pair on their boxes, face_box),
/// and a face the frustum may reach is tested by the lanes of each packet that enter the leaf
/// (test_leaf's lanes); true if a lane's hit changed. Every lane still tests each face it could
/// hit (a hit lies in the face's box, which the lane's own slab test then passes, and so does
/// the frustum's): the hits stay test_leaf's; most faces of a leaf lie beside a narrow frustum.
/// The packets share one watertight order: the corners are permuted once, by ps[0]'s.
template <bool Mixed>
BT_PK bool test_leaf_faces(Packet* ps, int np, const Frustum& fr, const BvhNode& node,
                           const Bvh& bvh, const TriangleMesh& mesh) {
    Mask lanes[kMaxWalkPackets];
    bool entered = false, changed = false;
    const std::uint32_t end = node.index + node.count;
    for (std::uint32_t k = node.index; k < end; k += 2) {
        const std::uint32_t faces[2] = {bvh.prim_ids[k], bvh.prim_ids[k + 1 < end ? k + 1 : k]};
        FaceCorners fc[2];
        BvhNode boxes[2];
        for (int i = 0; i < 2; ++i) {
            load_corners(mesh, faces[i], ps[0], fc[i]);
            face_box(fc[i], boxes[i]);
        }
        float e0 = 0.0f, e1 = 0.0f;
        unsigned reach = frustum_enters_pair<Mixed>(fr, boxes, e0, e1);
        if (k + 1 >= end) {
            reach &= 1u;
        }
        for (; reach != 0; reach &= reach - 1) {
            if (!entered) {
                for (int q = 0; q < np; ++q) {
                    vf unused;
                    lanes[q] = slab_lanes(ps[q], node, unused) & ps[q].active;
                }
                entered = true;
            }
            const int i = std::countr_zero(reach);
            for (int q = 0; q < np; ++q) {
                if (lanes[q] != 0) {
                    changed = test_face(ps[q], fc[i], faces[i], lanes[q]) || changed;
                }
            }
        }
    }
    return changed;
}

/// The fewest packets whose walk tests a leaf's faces against the frustum first
/// (test_leaf_faces): AVX2, AMD Zen 3, instructions against testing every face: the 19-sub-ray
/// beams' walks (32 packets) 0.75x, the airborne line's 64-ray walks (8) 0.91x, the car's 32-ray
/// walks (4, a spinning beam's wider frustum) 1.08x.
constexpr int kCullFacesPackets = 8;

/// walk_packet with interval culling: one test per child for the packets ps[0, np) together
/// (their frustum `fr`; Mixed: it may have mixed axes), and the lanes of each packet that enter
/// a leaf it reaches test its faces; a node is popped while some lane's limit may still reach it.
template <bool Mixed = false>
BT_PK void walk_frustum(Packet* ps, int np, Frustum& fr, const Bvh& bvh, const TriangleMesh& mesh) {
    struct Entry {
        float entry;
        std::uint32_t node;
    };
    Entry stack[128];
    int sp = 0;
    const BvhNode* nodes = bvh.nodes.data();
    float entry = 0.0f;
    if (!frustum_enters(fr, nodes[0], entry)) {
        return;
    }
    std::uint32_t index = 0;
    for (;;) {
        const BvhNode& node = nodes[index];
        if (node.is_leaf()) {
            bool changed = false;
            if (np >= kCullFacesPackets) {
                changed = test_leaf_faces<Mixed>(ps, np, fr, node, bvh, mesh);
            } else {
                for (int q = 0; q < np; ++q) {
                    changed = test_leaf(ps[q], node, bvh, mesh) || changed;
                }
            }
            if (changed) {
                fr.limit = beam_limit(ps, np);
            }
        } else {
            const std::uint32_t li = node.index, ri = node.index + 1;
            float el = 0.0f, er = 0.0f;
            const unsigned h = frustum_enters_pair<Mixed>(fr, &nodes[li], el, er);
            const bool hl = (h & 1u) != 0, hr = (h & 2u) != 0;
            if (hl && hr) {
                const bool left = el <= er;
                stack[sp++] = left ? Entry{er, ri} : Entry{el, li};
                index = left ? li : ri;
                continue;
            }
            if (hl || hr) {
                index = hl ? li : ri;
                continue;
            }
        }
        for (;;) {
            if (sp == 0) {
                return;
            }
            const Entry e = stack[--sp];
            if (e.entry <= fr.limit) {
                index = e.node;
                break;
            }
        }
    }
}

/// A stage of a batch as packets are made of it: its rays in float (`in`: as the batch has
/// them; `sorted`: in the order packets are made in, unless that is the same), their order and
/// the keys they were ordered by.
struct Stage {
    StageRays in, sorted;
    const StageRays* rays = &in;  ///< rays in packet order
    std::size_t first = 0;        ///< the batch's index of in's ray 0
    std::uint32_t keys[StageRays::kRays];
    std::uint16_t order[StageRays::kRays];
    std::uint64_t items[StageRays::kRays], spare[StageRays::kRays];  ///< sort_by_key's
};

/// NearestVisitor::store for the active lanes, lane l into the slot of the stage's ray at + l.
BT_PK void store_packet(const Packet& p, const Stage& st, std::size_t at, HitBatch& hits) {
    for (Mask m = p.active; m != 0; m &= m - 1) {
        const int l = std::countr_zero(m);
        const std::size_t i = st.first + st.order[at + static_cast<std::size_t>(l)];
        if (p.best_face[l] != kNoFace) {
            hits.t[i] = p.best_t[l];
            hits.face[i] = p.best_face[l];
            hits.u[i] = p.best_u[l];
            hits.v[i] = p.best_v[l];
        } else {
            hits.t[i] = std::numeric_limits<float>::infinity();
            hits.face[i] = kNoFace;
            hits.u[i] = hits.v[i] = 0.0f;
        }
    }
}

/// store_packet for a stage in the batch's order, the active lanes a prefix: lane l into the
/// slot of ray st.first + at + l, in lanes.
BT_PK void store_in_order(const Packet& p, const Stage& st, std::size_t at, HitBatch& hits) {
    const vi hit = p.best_face != kNoFace;
    const vf t = hit ? p.best_t : splat(std::numeric_limits<float>::infinity());
    const vf u = hit ? p.best_u : splat(0.0f), v = hit ? p.best_v : splat(0.0f);
    const std::size_t i = st.first + at;
    if (p.active == kAllLanes) {
        // A whole packet in one store per array: a copy of a variable size was a `rep movsq`
        // per array (~10 % of the 19-sub-ray survey's trace_beams on AVX2).
        __builtin_memcpy(&hits.t[i], &t, sizeof t);
        __builtin_memcpy(&hits.face[i], &p.best_face, sizeof p.best_face);
        __builtin_memcpy(&hits.u[i], &u, sizeof u);
        __builtin_memcpy(&hits.v[i], &v, sizeof v);
        return;
    }
    for (int l = 0; l < std::popcount(p.active); ++l) {
        const std::size_t j = i + static_cast<std::size_t>(l);
        hits.t[j] = t[l];
        hits.face[j] = p.best_face[l];
        hits.u[j] = u[l];
        hits.v[j] = v[l];
    }
}

/// Whether every active lane's direction is within acos(min_cos) of lane 0's of `ref` (the
/// scalar test's arithmetic: dot products in the same order).
BT_PK bool coherent(const Packet& p, float min_cos, const Packet& ref) {
    const float d0x = ref.d[0][0], d0y = ref.d[1][0], d0z = ref.d[2][0];
    const float n0 = d0x * d0x + d0y * d0y + d0z * d0z;
    const vf c = p.d[0] * d0x + p.d[1] * d0y + p.d[2] * d0z;
    const vf dd = p.d[0] * p.d[0] + p.d[1] * p.d[1] + p.d[2] * p.d[2];
    const vi ok = (c > 0.0f) & (c * c >= min_cos * min_cos * dd * n0);
    return (~lane_bits(ok) & p.active & (&p == &ref ? ~Mask{1} : kAllLanes)) == 0;
}

BT_PK bool coherent(const Packet& p, float min_cos) {
    return coherent(p, min_cos, p);
}

/// The widest spread of directions (cosine) a packet is traced with interval culling at (the
/// culling is conservative at any spread; wider packets only cull less). 0.97 takes the car's
/// spinning-scanner packets (a beam's 16 firings, about 48 mrad), which 0.9995 (32 mrad) left to
/// the lane-by-lane walk.
constexpr float kFrustumMinCos = 0.97f;  // 0.245 rad

/// Ray j of the stage as make_trace_ray makes it.
BT_PK TraceRay stage_ray(const StageRays& st, std::size_t j) {
    TraceRay r;
    r.org = Vec3f(st.o[0][j], st.o[1][j], st.o[2][j]);
    r.dir = Vec3f(st.d[0][j], st.d[1][j], st.d[2][j]);
    r.inv_dir = slab_inverse(r.dir);
    r.tmin = st.tmin[j];
    r.tmax = st.tmax[j];
    r.wt = make_watertight_ray(r.org, r.dir);
    return r;
}

/// The rays of a run that walk the tree as one frustum in trace_range: one packet of AVX-512 (a
/// spinning scanner's beam's 16 firings), four of AVX2. Packets of 8 walking apart took a walk
/// of the inner nodes each (~40 % of the car's trace_range). AVX2, AMD Zen 3, time against one
/// packet a walk: 16 rays car 0.85x, airborne 0.80x; 32 rays 0.80x, 0.65x; 64 rays 0.85x, 0.58x.
constexpr int kWalkRunRays = kLanes == 8 ? 32 : kLanes;
constexpr int kWalkRunPackets = kWalkRunRays / kLanes;
/// Rays a run piece loads: with AVX2 two walks' worth, which walk as one where their directions
/// lie within acos(kWideWalkMinCos) of the first (a line scanner's neighbouring pulses: the
/// 64-ray walk above), else as two walks of kWalkRunRays (a spinning scanner's beam, whose 64
/// firings fan out over ~13 degrees and walk slower as one).
constexpr int kRunRays = kLanes == 8 ? 2 * kWalkRunRays : kLanes;
constexpr int kRunPackets = kRunRays / kLanes;
static_assert(kRunPackets <= kMaxWalkPackets);
constexpr float kWideWalkMinCos = 0.9986f;  // 3 degrees

/// Whether packets ps[0, np) all lie within acos(min_cos) of ps[0]'s lane 0.
BT_PK bool all_coherent(const Packet* ps, int np, float min_cos) {
    for (int q = 0; q < np; ++q) {
        if (!coherent(ps[q], min_cos, ps[0])) {
            return false;
        }
    }
    return true;
}

/// The packets ps[0, np) (np at most kWalkRunPackets) of one watertight group through the
/// tree: as one frustum if their directions are within acos(kFrustumMinCos) of ps[0]'s lane 0
/// and bound every axis; else each packet alone, as a frustum of its own if there are several
/// and its directions are that close, or lane by lane.
BT_PK void walk_run_packets(Packet* ps, int np, const Bvh& bvh, const TriangleMesh& mesh) {
    Frustum fr;
    if (all_coherent(ps, np, kFrustumMinCos) && make_frustum(ps, np, false, fr)) {
        walk_frustum(ps, np, fr, bvh, mesh);
        return;
    }
    for (int q = 0; q < np; ++q) {
        if (np > 1 && coherent(ps[q], kFrustumMinCos) && make_frustum(&ps[q], 1, false, fr)) {
            walk_frustum(&ps[q], 1, fr, bvh, mesh);
        } else {
            walk_packet(ps[q], bvh, mesh);
        }
    }
}

/// The packets ps[0, np) of one watertight group through the tree: more than kWalkRunPackets as
/// one frustum where they are within acos(kWideWalkMinCos), else kWalkRunPackets at a time.
BT_PK void walk_packets(Packet* ps, int np, const Bvh& bvh, const TriangleMesh& mesh) {
    if (np > kWalkRunPackets) {
        Frustum fr;
        if (all_coherent(ps, np, kWideWalkMinCos) && make_frustum(ps, np, false, fr)) {
            walk_frustum(ps, np, fr, bvh, mesh);
            return;
        }
        for (int q = 0; q < np; q += kWalkRunPackets) {
            walk_run_packets(ps + q, std::min(kWalkRunPackets, np - q), bvh, mesh);
        }
        return;
    }
    walk_run_packets(ps, np, bvh, mesh);
}

/// Traces rays [at, at + n) of the stage (n at most kRunRays), of watertight group `group`, as
/// packets of kLanes (walk_packets); with `only_coherent`, a packet whose directions spread
/// wider than acos(min_cos) (or of one ray) is traced ray by ray.
BT_PK void trace_packet(const Stage& st, std::size_t at, int n, int group, const Bvh& bvh,
                        const TriangleMesh& mesh, HitBatch& hits, bool only_coherent,
                        float min_cos) {
    Packet ps[kRunPackets];
    std::size_t from[kRunPackets];
    int np = 0;
    for (int q = 0; q * kLanes < n; ++q) {
        const std::size_t j = at + static_cast<std::size_t>(q) * kLanes;
        const int k = std::min(kLanes, n - q * kLanes);
        load_packet(ps[np], *st.rays, j, k, group);
        if (only_coherent && (k == 1 || !coherent(ps[np], min_cos))) {
            for (std::size_t i = j; i < j + static_cast<std::size_t>(k); ++i) {
                trace_single(bvh, mesh, stage_ray(*st.rays, i), hits, st.first + st.order[i]);
            }
            continue;
        }
        from[np++] = j;
    }
    if (np == 0) {
        return;
    }
    walk_packets(ps, np, bvh, mesh);
    for (int q = 0; q < np; ++q) {
        store_packet(ps[q], st, from[q], hits);
    }
}

/// A coordinate in [-1, 1] in 12 bits, lane by lane (NaN and outside: the nearest end).
BT_PK vu quantise(vf s) {
    const vf q = (s + 1.0f) * 2048.0f;
    const vf c = q > 0.0f ? (q < 4095.0f ? q : splat(4095.0f)) : splat(0.0f);
    return reinterpret_cast<vu>(__builtin_convertvector(c, vi));
}

/// Which way a direction component points: 0 down the axis, 1 not at all (or NaN), 2 up.
BT_PK vu sign_class(vf x) {
    return x > 0.0f ? splat_u(2) : (x < 0.0f ? splat_u(0) : splat_u(1));
}

/// The watertight test's axis order lane by lane, as make_watertight_ray picks it: z0 (kz = 0),
/// z1 (kz = 1; else kz = 2), the direction's component along kz and the group 2 kz + whether kx
/// and ky swap (dk < 0).
struct AxisOrder {
    vi z0, z1;
    vf dk;
    vu group;
};

BT_PK AxisOrder axis_order(const vf d[3]) {
    const vf ax = vabs(d[0]), ay = vabs(d[1]), az = vabs(d[2]);
    AxisOrder k;
    k.z0 = (ax > ay) & (ax > az);
    k.z1 = ~(ax > ay) & (ay > az);
    const vu kz = k.z0 ? splat_u(0) : (k.z1 ? splat_u(1) : splat_u(2));
    k.dk = k.z0 ? d[0] : (k.z1 ? d[1] : d[2]);
    k.group = 2 * kz + (k.dk < 0.0f ? splat_u(1) : splat_u(0));
    return k;
}

/// Where rays go in the order packets are made in, lane by lane: their packet group in the top
/// 8 bits (the watertight axis order, kz and whether kx, ky swap, as make_watertight_ray picks
/// it, then which way the two other components point: a packet of one group has one sign per
/// axis, which interval culling needs), then their direction as two coordinates in [-1, 1]
/// over the dominant axis: the sine of the elevation (when mostly horizontal) or the x slope
/// (mostly vertical), then the other horizontal slope.
BT_PK vu order_keys(const vf d[3]) {
    const AxisOrder k = axis_order(d);
    const vi z0 = k.z0, z1 = k.z1;
    const vf dk = k.dk;
    const vf da = z0 ? d[1] : (z1 ? d[2] : d[0]);  // the axes after kz, unswapped
    const vf db = z0 ? d[2] : (z1 ? d[0] : d[1]);
    const vu group = (k.group * 9 + 3 * sign_class(da)) + sign_class(db);
    const vf adk = vabs(dk);
    const vf dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const vi vertical = ~(z0 | z1);
    const vf u = vertical ? d[0] / adk : d[2] / lanes_sqrt(dd);
    const vf v = (z1 ? d[0] : d[1]) / adk;
    return (group << 24) | (quantise(u) << 12) | quantise(v);
}

/// The packet group in a ray's key, and its watertight group (2 kz + whether kx, ky swap).
BT_PK std::uint32_t packet_group(std::uint32_t key) {
    return key >> 24;
}

/// kLanes doubles from x (count of them, the rest 0) in float (a whole packet's: lanes_to_float).
BT_PK vf to_float(const double* x, std::size_t count) {
    if (count >= kLanes) {
        return lanes_to_float(x);
    }
    vf r = splat(0.0f);
    for (std::size_t l = 0; l < count; ++l) {
        r[l] = static_cast<float>(x[l]);
    }
    return r;
}

/// Rays [first, first + n) of the batch into st.in (make_box_ray's conversions, in lanes) and
/// their order keys (`sorted`: else only the watertight group in them, for beams in their order).
BT_PK void stage_rays(Stage& st, const RayBatch& rays, std::size_t first, std::size_t n,
                      bool sorted = true) {
    st.first = first;
    const double* src[8] = {rays.ox.data(), rays.oy.data(), rays.oz.data(),   rays.dx.data(),
                            rays.dy.data(), rays.dz.data(), rays.tmin.data(), rays.tmax.data()};
    float* dst[8] = {st.in.o[0], st.in.o[1], st.in.o[2], st.in.d[0],
                     st.in.d[1], st.in.d[2], st.in.tmin, st.in.tmax};
    for (std::size_t j = 0; j < n; j += kLanes) {
        vf dir[3];
        for (int k = 0; k < 8; ++k) {
            const vf f = to_float(src[k] + first + j, n - j);
            __builtin_memcpy(dst[k] + j, &f, sizeof f);
            if (k >= 3 && k < 6) {
                dir[k - 3] = f;
            }
        }
        const vu key = sorted ? order_keys(dir) : (axis_order(dir).group * 9) << 24;
        if (n - j >= kLanes) {
            __builtin_memcpy(st.keys + j, &key, sizeof key);
        } else {
            __builtin_memcpy(st.keys + j, &key, (n - j) * 4);
        }
    }
    // A packet's loads may read kLanes floats past the last ray: zeros there.
    const std::size_t end = (n + kLanes - 1) / kLanes * kLanes;
    for (float* x : dst) {
        std::fill(x + end, x + end + kLanes, 0.0f);
    }
}

/// A stage whose keys descend at most this often is left in its order and cut into packets at
/// the descents (trace_range): a line scanner's stage is one or two rising runs (a sawtooth wraps
/// once in 2000 pulses), whose sort cost more than the few partial packets at a wrap.
constexpr std::size_t kMaxDescents = 4;

/// order[0..n) = 0..n-1 sorted by keys; false if that left them in place (a stable LSD radix sort
/// of the keys less the least, in as few passes of at most 9 bits as their range needs: a line
/// scanner's stage differs in its across-track slope only, two passes of 6 bits; none when the keys
/// descend at most kMaxDescents times: they are in order, or a few runs that are). The items
/// sorted are (key - least) << 16 | index, in `items` and `spare` (n each): the passes read no
/// key through the order, and every pass's counts are made in one read of the keys (a car's
/// stage took three passes, ~25 % of its trace_range on AVX2 when each read its keys via order).
BT_PK bool sort_by_key(const std::uint32_t* keys, std::size_t n, std::uint16_t* order,
                       std::uint64_t* items, std::uint64_t* spare) {
    std::uint32_t lo = ~std::uint32_t{0}, hi = 0;
    std::size_t descents = 0;
    for (std::size_t j = 0; j < n; ++j) {
        order[j] = static_cast<std::uint16_t>(j);
        descents += j > 0 && keys[j] < keys[j - 1] ? 1 : 0;
        lo = std::min(lo, keys[j]);
        hi = std::max(hi, keys[j]);
    }
    const int bits = n == 0 || descents <= kMaxDescents ? 0 : std::bit_width(hi - lo);
    const int passes = (bits + 8) / 9;
    if (passes == 0) {
        return false;
    }
    const int width = (bits + passes - 1) / passes;
    const std::uint64_t digit = (std::uint64_t{1} << width) - 1;
    // Each pass scatters the two halves of its items at once, each with its own counts (the
    // second half's bucket starts after the first half's items in it: stable still), so two
    // chains of count increments run side by side.
    const std::size_t half = n / 2;
    std::uint32_t count[4][513] = {};
    for (std::size_t j = 0; j < n; ++j) {
        items[j] = std::uint64_t{keys[j] - lo} << 16 | j;
        for (int pass = 0; pass < passes; ++pass) {
            ++count[pass][((items[j] >> (16 + pass * width)) & digit) + 1];
        }
    }
    for (int pass = 0; pass < passes; ++pass) {
        std::uint32_t c0[513] = {}, c1[513];
        for (std::size_t j = 0; j < half; ++j) {
            ++c0[((items[j] >> (16 + pass * width)) & digit) + 1];
        }
        std::uint32_t at = 0;
        for (std::uint64_t b = 1; b < digit + 2; ++b) {
            const std::uint32_t first = c0[b], all = count[pass][b];
            c0[b] = at;
            c1[b] = at + first;
            at += all;
        }
        const int shift = 16 + pass * width;
        for (std::size_t j = 0; j < half; ++j) {
            const std::uint64_t a = items[j], b = items[half + j];
            spare[c0[((a >> shift) & digit) + 1]++] = a;
            spare[c1[((b >> shift) & digit) + 1]++] = b;
        }
        for (std::size_t j = 2 * half; j < n; ++j) {
            spare[c1[((items[j] >> shift) & digit) + 1]++] = items[j];
        }
        std::swap(items, spare);
    }
    for (std::size_t j = 0; j < n; ++j) {
        order[j] = static_cast<std::uint16_t>(items[j]);
    }
    return true;
}

/// Puts the stage's n rays in packet order (st.rays), or leaves them where they are if that is
/// the order they came in.
BT_PK void order_stage(Stage& st, std::size_t n) {
    const bool moved = sort_by_key(st.keys, n, st.order, st.items, st.spare);
    st.rays = moved ? &st.sorted : &st.in;
    if (!moved) {
        return;
    }
    for (std::size_t o = 0; o < n; ++o) {
        const std::size_t j = st.order[o];
        for (std::size_t a = 0; a < 3; ++a) {
            st.sorted.o[a][o] = st.in.o[a][j];
            st.sorted.d[a][o] = st.in.d[a][j];
        }
        st.sorted.tmin[o] = st.in.tmin[j];
        st.sorted.tmax[o] = st.in.tmax[j];
    }
    for (float* x : {st.sorted.o[0], st.sorted.o[1], st.sorted.o[2], st.sorted.d[0], st.sorted.d[1],
                     st.sorted.d[2], st.sorted.tmin, st.sorted.tmax}) {
        std::fill(x + n, x + n + kLanes, 0.0f);
    }
}

/// Rays [at, end) of a stage in packet order, each run of one packet group whose keys rise (all
/// of a sorted stage's group) cut into pieces of kRunRays that are loaded whole.
BT_PK void trace_runs(const Stage& st, std::size_t at, std::size_t end, const Bvh& bvh,
                      const TriangleMesh& mesh, HitBatch& hits, bool only_coherent, float min_cos) {
    while (at < end) {
        const std::uint32_t group = packet_group(st.keys[st.order[at]]);
        std::size_t run = at + 1;
        while (run < end && packet_group(st.keys[st.order[run]]) == group &&
               st.keys[st.order[run]] >= st.keys[st.order[run - 1]]) {
            ++run;
        }
        while (at < run) {
            const std::size_t k = std::min<std::size_t>(kRunRays, run - at);
            trace_packet(st, at, static_cast<int>(k), static_cast<int>(group / 9), bvh, mesh, hits,
                         only_coherent, min_cos);
            at += k;
        }
    }
}

BT_PK_ENTRY void trace_range(const Bvh& bvh, const TriangleMesh& mesh, const RayBatch& rays,
                             std::size_t begin, std::size_t end, HitBatch& hits, bool only_coherent,
                             float min_cos) {
    // A stage of rays is converted to float in lanes, put in the order of their packet group and
    // direction (a spinning scanner's fan of beams then gives packets of one beam's neighbouring
    // pulses) unless it is a few rising runs already, and each group's rising run is cut into
    // packets that are loaded whole.
    Stage st;
    for (std::size_t first = begin; first < end; first += StageRays::kRays) {
        const std::size_t n = std::min(StageRays::kRays, end - first);
        stage_rays(st, rays, first, n);
        order_stage(st, n);
        trace_runs(st, 0, n, bvh, mesh, hits, only_coherent, min_cos);
    }
}

/// Whether a key of keys[0, n) lies outside [lo, lo + span): one unsigned compare a key, kLanes
/// at a time (keys past n are not read).
BT_PK bool keys_outside(const std::uint32_t* keys, std::size_t n, std::uint32_t lo,
                        std::uint32_t span) {
    const vu vlo = splat_u(lo), vspan = splat_u(span);
    vi out = vi{};
    std::size_t j = 0;
    for (; j + kLanes <= n; j += kLanes) {
        vu k;
        __builtin_memcpy(&k, keys + j, sizeof k);
        out |= (k - vlo) >= vspan;
    }
    bool tail = false;
    for (; j < n; ++j) {
        tail |= keys[j] - lo >= span;
    }
    return tail || lane_bits(out) != 0;
}

/// Rays [at, at + n) of an unsorted stage (n at most kWalkRays: whole beams of sub-rays) as
/// packets of kLanes of them that walk the tree as one frustum (mixed axes allowed: a narrow
/// beam about a plane of an axis has lanes moving up and down it), each lane testing the faces
/// of the leaves its own slab test enters. False if they differ in the watertight axis order,
/// or, with `split`, their directions spread too wide for one frustum (then nothing is traced:
/// a sawtooth's wrap falls between two beams of a walk).
BT_PK bool trace_walk(const Stage& st, std::size_t at, std::size_t n, bool split, const Bvh& bvh,
                      const TriangleMesh& mesh, HitBatch& hits, bool only_coherent, float min_cos) {
    // Keys of one watertight group (packet_group / 9) lie in [9 g << 24, (9 g + 9) << 24).
    const std::uint32_t group = packet_group(st.keys[at]) / 9;
    if (keys_outside(st.keys + at, n, group * 9 << 24, 9u << 24)) {
        return false;
    }
    Packet ps[kBeamPackets];
    const int np = static_cast<int>((n + kLanes - 1) / kLanes);
    bool narrow = true, wanted = true;
    for (int q = 0; q < np; ++q) {
        const std::size_t from = static_cast<std::size_t>(q) * kLanes;
        load_packet(ps[q], *st.rays, at + from,
                    static_cast<int>(std::min<std::size_t>(kLanes, n - from)),
                    static_cast<int>(group));
        // Within min_cos of each other, the rays are within kFrustumMinCos too (min_cos is
        // the stricter): one test then.
        const bool near_enough = only_coherent && coherent(ps[q], min_cos, ps[0]);
        wanted = wanted && (!only_coherent || near_enough);
        narrow = narrow && ((near_enough && min_cos >= kFrustumMinCos) ||
                            coherent(ps[q], kFrustumMinCos, ps[0]));
    }
    if (split && !(narrow && wanted)) {
        return false;
    }
    if (!wanted) {
        for (std::size_t j = at; j < at + n; ++j) {
            trace_single(bvh, mesh, stage_ray(*st.rays, j), hits, st.first + j);
        }
        return true;
    }
    Frustum fr;
    if (narrow && make_frustum(ps, np, true, fr)) {
        walk_frustum<true>(ps, np, fr, bvh, mesh);
    } else {
        for (int q = 0; q < np; ++q) {
            walk_packet(ps[q], bvh, mesh);
        }
    }
    for (int q = 0; q < np; ++q) {
        store_in_order(ps[q], st, at + static_cast<std::size_t>(q) * kLanes, hits);
    }
    return true;
}

/// trace_range for rays in beams of `per_beam` (at most kWalkRays): as many whole beams as
/// kWalkRays holds walk the tree together (trace_walk), in the order the rays come in; where
/// their watertight axis orders differ (or their directions spread too wide), beam by beam, and
/// a beam whose own rays differ in it in runs of one packet group (trace_runs).
BT_PK_ENTRY void trace_beams(const Bvh& bvh, const TriangleMesh& mesh, const RayBatch& rays,
                             std::size_t begin, std::size_t end, std::size_t per_beam,
                             HitBatch& hits, bool only_coherent, float min_cos) {
    Stage st;
    const std::size_t walk = kWalkRays / per_beam * per_beam;
    const std::size_t stage = StageRays::kRays / walk * walk;
    for (std::size_t j = 0; j < stage; ++j) {
        st.order[j] = static_cast<std::uint16_t>(j);
    }
    st.rays = &st.in;
    for (std::size_t first = begin; first < end; first += stage) {
        const std::size_t n = std::min(stage, end - first);
        stage_rays(st, rays, first, n, false);
        for (std::size_t at = 0; at < n; at += walk) {
            const std::size_t m = std::min(walk, n - at);
            if (trace_walk(st, at, m, m > per_beam, bvh, mesh, hits, only_coherent, min_cos)) {
                continue;
            }
            for (std::size_t b = at; b < at + m; b += per_beam) {
                const std::size_t k = std::min(per_beam, at + m - b);
                if (!trace_walk(st, b, k, false, bvh, mesh, hits, only_coherent, min_cos)) {
                    trace_runs(st, b, b + k, bvh, mesh, hits, only_coherent, min_cos);
                }
            }
        }
    }
}
