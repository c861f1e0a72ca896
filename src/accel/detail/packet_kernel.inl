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

/// NearestVisitor::visit of face `face` in the lanes of `mask`.
BT_PK void test_face(Packet& p, const TriangleMesh& mesh, std::uint32_t face, Mask mask) {
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
    walk_packet(p, bvh, mesh);
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

/// order[0..n) = 0..n-1 sorted by keys (stable LSD radix sort, 3 passes of 9 bits; 27-bit keys).
BT_PK void sort_by_key(const std::uint32_t* keys, std::size_t n, std::uint16_t* order,
                       std::uint16_t* scratch) {
    for (std::size_t j = 0; j < n; ++j) {
        order[j] = static_cast<std::uint16_t>(j);
    }
    for (int shift = 0; shift < 27; shift += 9) {
        std::uint32_t count[513] = {};
        for (std::size_t j = 0; j < n; ++j) {
            ++count[((keys[order[j]] >> shift) & 511u) + 1];
        }
        for (int b = 0; b < 512; ++b) {
            count[b + 1] += count[b];
        }
        for (std::size_t j = 0; j < n; ++j) {
            scratch[count[(keys[order[j]] >> shift) & 511u]++] = order[j];
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
