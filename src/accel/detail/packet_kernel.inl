// The packet kernel, included by packet_trace.cpp once per instruction set inside a namespace
// that defines kLanes, the vector types vf (float), vi (int32, what comparisons give) and vu
// (uint32), lane_bits(vi) (one bit per lane), BT_PK (inline helpers) and BT_PK_ENTRY (the
// entry point), all compiled for that instruction set. Every float expression below is the
// scalar one of trace_ray.hpp / ray_triangle.hpp / queries.hpp in lanes, operand for operand.

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

/// All bits set in the lanes of `m` (a comparison's form of a lane mask).
BT_PK vi lanes_of(Mask m) {
    vi r{};
    for (int l = 0; l < kLanes; ++l) {
        r[l] = ((m >> l) & 1u) != 0 ? -1 : 0;
    }
    return r;
}

BT_PK vf vabs(vf x) {
    return reinterpret_cast<vf>(reinterpret_cast<vu>(x) & splat_u(0x7fffffffu));
}

/// One packet: the rays of TraceRay, lane by lane, and each lane's NearestVisitor state.
struct Packet {
    vf o[3];    ///< origin by axis
    vf inv[3];  ///< 1 / direction by axis
    vf ok[3];   ///< origin in the watertight order (kx, ky, kz)
    vf sx, sy, sz;
    vf tmin;
    vf limit;  ///< the nearest hit so far and a few ulps (NearestVisitor's limit)
    vf best_t, best_u, best_v;
    vu best_face;
    std::size_t kx = 0, ky = 1, kz = 2;
    Mask active = 0;
    const TraceRay* const* rays = nullptr;  ///< the lanes' rays (for the double edge case)
};

/// Lanes [0, n) from *rays[0..n), which share the watertight axis order; lanes past n copy ray
/// 0 and stay inactive.
BT_PK void load_packet(Packet& p, const TraceRay* const* rays, int n) {
    p.rays = rays;
    p.kx = static_cast<std::size_t>(rays[0]->wt.kx);
    p.ky = static_cast<std::size_t>(rays[0]->wt.ky);
    p.kz = static_cast<std::size_t>(rays[0]->wt.kz);
    for (int l = 0; l < kLanes; ++l) {
        const TraceRay& r = *rays[l < n ? l : 0];
        for (std::size_t a = 0; a < 3; ++a) {
            p.o[a][l] = r.org[a];
            p.inv[a][l] = r.inv_dir[a];
        }
        p.ok[0][l] = r.org[p.kx];
        p.ok[1][l] = r.org[p.ky];
        p.ok[2][l] = r.org[p.kz];
        p.sx[l] = r.wt.sx;
        p.sy[l] = r.wt.sy;
        p.sz[l] = r.wt.sz;
        p.tmin[l] = r.tmin;
        p.best_t[l] = r.tmax;
        p.limit[l] = r.tmax * kNearestRoom;
    }
    p.best_u = p.best_v = splat(0.0f);
    p.best_face = splat_u(kNoFace);
    p.active = n >= kLanes ? kAllLanes : (Mask{1} << n) - 1;
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
    const TraceRay& r = *p.rays[l];
    if (intersect_watertight(r.wt, a, b, c, r.tmin, p.limit[l], Facing::both, h) &&
        (h.t < p.best_t[l] || (h.t == p.best_t[l] && face < p.best_face[l]))) {
        p.best_t[l] = h.t;
        p.limit[l] = h.t * kNearestRoom;
        p.best_face[l] = face;
        p.best_u[l] = h.u;
        p.best_v[l] = h.v;
    }
}

/// NearestVisitor::visit of face `face` in the lanes of `mask`; true if a lane's hit changed.
BT_PK bool test_face(Packet& p, const TriangleMesh& mesh, std::uint32_t face, Mask mask) {
    const Face& f = mesh.faces[face];
    const Vec3f& a = mesh.vertices[f[0]];
    const Vec3f& b = mesh.vertices[f[1]];
    const Vec3f& c = mesh.vertices[f[2]];
    const vf Akx = a[p.kx] - p.ok[0], Aky = a[p.ky] - p.ok[1], Akz = a[p.kz] - p.ok[2];
    const vf Bkx = b[p.kx] - p.ok[0], Bky = b[p.ky] - p.ok[1], Bkz = b[p.kz] - p.ok[2];
    const vf Ckx = c[p.kx] - p.ok[0], Cky = c[p.ky] - p.ok[1], Ckz = c[p.kz] - p.ok[2];
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
    const vf inv = 1.0f / det;
    const vf t = T * inv;
    const vi hit = ~outside & (det != 0.0f) & ~clipped & (t >= p.tmin) & (t <= p.limit);
    const vi better = (t < p.best_t) | ((t == p.best_t) & (face < p.best_face));
    const Mask edge = lane_bits(zero) & mask;
    const Mask take = lane_bits(hit & better) & mask & ~edge;
    if (take != 0) {
        const vi k = lanes_of(take);
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
/// Every lane then tests the faces of every node the packet enters; the hits stay the single-ray
/// walk's, since each lane still tests every face its own walk would (see packet_trace.hpp).
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
    float tmin = 0;        ///< least tmin of the active lanes
    float limit = 0;       ///< greatest limit of the active lanes
    // The fields above twice over (a node's two children tested at once), made by make_frustum.
    v8 near_org2, far_org2, inv_lo2, inv_hi2, org_lo2, org_hi2;
    v8i near_hi2, free2, still2;
};

BT_PK float active_min(vf x, Mask active) {
    float m = std::numeric_limits<float>::infinity();
    for (Mask k = active; k != 0; k &= k - 1) {
        const float v = x[std::countr_zero(k)];
        m = v < m ? v : m;
    }
    return m;
}

BT_PK float active_max(vf x, Mask active) {
    float m = -std::numeric_limits<float>::infinity();
    for (Mask k = active; k != 0; k &= k - 1) {
        const float v = x[std::countr_zero(k)];
        m = v > m ? v : m;
    }
    return m;
}

/// The bounds of axis a over the active lanes; false if the lanes' inverse directions neither
/// share a sign and are finite nor are all infinite (the axis then bounds nothing).
BT_PK bool bound_axis(const Packet& p, int a, Frustum& fr) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const vf inv = p.inv[a];
    const Mask pos = lane_bits((inv > 0.0f) & (inv < kInf)) & p.active;
    const Mask neg = lane_bits((inv < 0.0f) & (inv > -kInf)) & p.active;
    const Mask still = lane_bits(vabs(inv) == kInf) & p.active;
    const float olo = active_min(p.o[a], p.active), ohi = active_max(p.o[a], p.active);
    fr.org_lo[a] = olo;
    fr.org_hi[a] = ohi;
    fr.free[a] = -1;
    fr.still[a] = still == p.active ? -1 : 0;
    fr.near_hi[a] = neg == p.active ? -1 : 0;
    fr.inv_lo[a] = fr.inv_hi[a] = 0.0f;
    fr.near_org[a] = fr.far_org[a] = 0.0f;
    if (pos != p.active && neg != p.active) {
        return still == p.active;
    }
    fr.free[a] = 0;
    fr.inv_lo[a] = active_min(inv, p.active);
    fr.inv_hi[a] = active_max(inv, p.active);
    // Moving up the axis, the near plane's (lo - o) * inv is least from the greatest origin and
    // the far plane's greatest from the least; moving down, the other way round.
    fr.near_org[a] = pos == p.active ? ohi : olo;
    fr.far_org[a] = pos == p.active ? olo : ohi;
    return true;
}

/// The packet's frustum; false if an axis bounds nothing (the lanes' directions differ in sign
/// or some are zero along it), so that culling by it would visit far too many nodes.
BT_PK bool make_frustum(const Packet& p, Frustum& fr) {
    fr.near_org = fr.far_org = fr.inv_lo = fr.inv_hi = fr.org_lo = fr.org_hi = v4{};
    fr.near_hi = fr.still = v4i{};
    fr.free = v4i{-1, -1, -1, -1};
    bool bounded = true;
    for (int a = 0; a < 3; ++a) {
        bounded = bound_axis(p, a, fr) && bounded;
    }
    fr.tmin = active_min(p.tmin, p.active);
    fr.limit = active_max(p.limit, p.active);
    fr.near_org2 = twice(fr.near_org);
    fr.far_org2 = twice(fr.far_org);
    fr.inv_lo2 = twice(fr.inv_lo);
    fr.inv_hi2 = twice(fr.inv_hi);
    fr.org_lo2 = twice(fr.org_lo);
    fr.org_hi2 = twice(fr.org_hi);
    fr.near_hi2 = twice(fr.near_hi);
    fr.free2 = twice(fr.free);
    fr.still2 = twice(fr.still);
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

/// frustum_enters for the two children of an inner node at once (nodes[0] and nodes[1], 64
/// bytes side by side), the same arithmetic lane for lane: bit 0 if the first may be entered,
/// bit 1 the second.
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

/// walk_packet with interval culling: one test per child for the whole packet, and every
/// active lane tests the faces of the leaves it reaches; a node is popped while some lane's
/// limit may still reach it.
BT_PK void walk_frustum(Packet& p, Frustum& fr, const Bvh& bvh, const TriangleMesh& mesh) {
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
            for (std::uint32_t k = node.index; k < node.index + node.count; ++k) {
                changed = test_face(p, mesh, bvh.prim_ids[k], p.active) || changed;
            }
            if (changed) {
                fr.limit = active_max(p.limit, p.active);
            }
        } else {
            const std::uint32_t li = node.index, ri = node.index + 1;
            float el = 0.0f, er = 0.0f;
            const unsigned h = frustum_enters_pair(fr, &nodes[li], el, er);
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

/// NearestVisitor::store for the active lanes, lane l into slot slots[l].
BT_PK void store_packet(const Packet& p, const std::size_t* slots, HitBatch& hits) {
    for (Mask m = p.active; m != 0; m &= m - 1) {
        const int l = std::countr_zero(m);
        const std::size_t i = slots[l];
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

/// Rays waiting for a packet, grouped by the watertight axis order (kz and whether kx, ky swap).
struct Groups {
    static constexpr int kKeys = 6;
    const TraceRay* rays[kKeys][kLanes];
    std::size_t slots[kKeys][kLanes];
    int fill[kKeys] = {};
};

BT_PK bool coherent(const TraceRay* const* rays, int n, float min_cos) {
    const Vec3f d0 = rays[0]->dir;
    const float n0 = dot(d0, d0);
    for (int l = 1; l < n; ++l) {
        const Vec3f d = rays[l]->dir;
        const float c = dot(d, d0);
        if (!(c > 0.0f && c * c >= min_cos * min_cos * dot(d, d) * n0)) {
            return false;
        }
    }
    return true;
}

/// The widest spread of directions (cosine) a packet is traced with interval culling at.
constexpr float kFrustumMinCos = 0.9995f;  // 0.032 rad

BT_PK void flush(Groups& g, int key, const Bvh& bvh, const TriangleMesh& mesh, HitBatch& hits,
                 bool only_coherent, float min_cos) {
    const int n = g.fill[key];
    g.fill[key] = 0;
    if (n == 0) {
        return;
    }
    if (only_coherent && (n == 1 || !coherent(g.rays[key], n, min_cos))) {
        for (int l = 0; l < n; ++l) {
            trace_single(bvh, mesh, *g.rays[key][l], hits, g.slots[key][l]);
        }
        return;
    }
    Packet p;
    load_packet(p, g.rays[key], n);
    Frustum fr;
    if (coherent(g.rays[key], n, kFrustumMinCos) && make_frustum(p, fr)) {
        walk_frustum(p, fr, bvh, mesh);
    } else {
        walk_packet(p, bvh, mesh);
    }
    store_packet(p, g.slots[key], hits);
}

/// A coordinate in [-1, 1] in 12 bits (NaN and outside: the nearest end).
BT_PK std::uint32_t quantise(float s) {
    const float q = (s + 1.0f) * 2048.0f;
    return q > 0.0f ? (q < 4095.0f ? static_cast<std::uint32_t>(q) : 4095u) : 0u;
}

/// The packet group of a ray (its watertight axis order: kz and whether kx, ky swap).
BT_PK int group_of(const TraceRay& r) {
    return 2 * r.wt.kz + (r.wt.kx == (r.wt.kz + 1) % 3 ? 0 : 1);
}

/// Where a ray goes in the order packets are made in: its group, then its direction as two
/// coordinates in [-1, 1] over the dominant axis: the sine of its elevation (when it is mostly
/// horizontal) or its x slope (mostly vertical), then the other horizontal slope.
BT_PK std::uint32_t order_key(const TraceRay& r) {
    const auto kz = static_cast<std::size_t>(r.wt.kz);
    const Vec3f d = r.dir;
    float u = 0.0f, v = 0.0f;
    if (kz == 2) {
        u = d.x / std::fabs(d.z);
        v = d.y / std::fabs(d.z);
    } else {
        u = d.z / std::sqrt(dot(d, d));
        v = d[1 - kz] / std::fabs(d[kz]);
    }
    const auto g = static_cast<std::uint32_t>(group_of(r));
    return (g << 24) | (quantise(u) << 12) | quantise(v);
}

/// order[0..n) = 0..n-1 sorted by keys (a stable LSD radix sort of the keys less the least, in as
/// few passes of at most 9 bits as their range needs: a line scanner's stage differs in its
/// across-track slope only, two passes of 6 bits; none when every key is the same).
BT_PK void sort_by_key(const std::uint32_t* keys, std::size_t n, std::uint16_t* order,
                       std::uint16_t* scratch) {
    std::uint32_t lo = ~std::uint32_t{0}, hi = 0;
    for (std::size_t j = 0; j < n; ++j) {
        order[j] = static_cast<std::uint16_t>(j);
        lo = std::min(lo, keys[j]);
        hi = std::max(hi, keys[j]);
    }
    const int bits = n == 0 ? 0 : std::bit_width(hi - lo);
    const int passes = (bits + 8) / 9;
    if (passes == 0) {
        return;
    }
    const int width = (bits + passes - 1) / passes;
    const std::uint32_t digit = (std::uint32_t{1} << width) - 1;
    for (int shift = 0; shift < passes * width; shift += width) {
        std::uint32_t count[513] = {};
        for (std::size_t j = 0; j < n; ++j) {
            ++count[(((keys[order[j]] - lo) >> shift) & digit) + 1];
        }
        for (std::uint32_t b = 0; b < digit + 1; ++b) {
            count[b + 1] += count[b];
        }
        for (std::size_t j = 0; j < n; ++j) {
            scratch[count[((keys[order[j]] - lo) >> shift) & digit]++] = order[j];
        }
        std::copy(scratch, scratch + n, order);
    }
}

BT_PK_ENTRY void trace_range(const Bvh& bvh, const TriangleMesh& mesh, const RayBatch& rays,
                             std::size_t begin, std::size_t end, HitBatch& hits, bool only_coherent,
                             float min_cos) {
    // The rays of a stage are made in place (copying them whole into their group stalls on
    // store forwarding), put in the order of their direction within their group (a spinning
    // scanner's fan of beams then gives packets of one beam's neighbouring pulses), and every
    // group is traced before the next stage overwrites them.
    constexpr std::size_t kStage = 1024;
    TraceRay staged[kStage];
    std::uint32_t keys[kStage];
    std::uint16_t order[kStage], scratch[kStage];
    Groups g;
    for (std::size_t first = begin; first < end; first += kStage) {
        const std::size_t n = std::min(kStage, end - first);
        for (std::size_t j = 0; j < n; ++j) {
            ::new (static_cast<void*>(&staged[j])) TraceRay(make_trace_ray(rays, first + j));
            keys[j] = order_key(staged[j]);
        }
        sort_by_key(keys, n, order, scratch);
        for (std::size_t o = 0; o < n; ++o) {
            const std::size_t j = order[o];
            const TraceRay& r = staged[j];
            const int key = group_of(r);
            const int k = g.fill[key]++;
            g.rays[key][k] = &r;
            g.slots[key][k] = first + j;
            if (k + 1 == kLanes) {
                flush(g, key, bvh, mesh, hits, only_coherent, min_cos);
            }
        }
        for (int key = 0; key < Groups::kKeys; ++key) {
            flush(g, key, bvh, mesh, hits, only_coherent, min_cos);
        }
    }
}
