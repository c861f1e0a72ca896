// The Embree 3 backend: Intel's kernels behind the same batch interface as our own backends.
//
// - One RTCDevice per backend. Embree's TBB threads only build the BVHs (while our pool waits);
//   tracing runs on our ThreadPool. Nearest hits go 16 rays at a time through rtcIntersect16
//   (incoherent mode: watertight, about 1.2x rtcIntersect1 on survey rays), in packets aligned on
//   absolute ray indices so results never depend on the thread count or on how batches are
//   split; occlusion and all-hits are one rtcOccluded1/rtcIntersect1 per ray.
// - Meshes are Embree triangle geometries over our own buffers (rtcNewSharedBuffer). Embree reads
//   vertices with 16-byte loads, so the last vertex needs 4 readable bytes after it: we share the
//   vertex vector when its capacity leaves that slack, and otherwise copy the vertices once per
//   mesh into an Embree buffer with the padding. Index buffers are always shared.
// - Instances placed with the identity are plain geometries of the top scene; other instances are
//   RTC_GEOMETRY_TYPE_INSTANCE of one committed sub-scene per mesh (triangles never copied). Every
//   top-level geometry has the ID of its instance, so global face = first_face + primID.
// - Exact spheres are one RTC_GEOMETRY_TYPE_SPHERE_POINT geometry of the top scene (x, y, z,
//   radius per sphere), after the instances; primID indexes SceneGeometry::spheres. Embree's
//   roots are single precision, ours (sphere_roots) double from the same float ray. In all-hits
//   a sphere's side comes from Embree's outward Ng.
// - All-hits is a context filter that records each candidate and rejects it (valid = 0), then the
//   hits are sorted by (t, face) and deduplicated as in our own backends. The side is computed
//   from our own triangle data (normal (b - a) x (c - a) against the ray direction in object
//   coordinates, swapped for mirroring placements), not from Embree's Ng, so it follows
//   ray_triangle.hpp's convention exactly.
// - Embree's nearest hit at exactly equal range on two faces (a ray through a shared edge) is
//   whichever Embree finds first, not necessarily the lowest face ID; the range is the same.
#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <vector>

#include "accel/embree_rays.hpp"
#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/error.hpp"
#include "detail/embree.hpp"
#include "detail/queries.hpp"

namespace beamtrace::detail {
namespace {

/// Where a top-level geometry's faces go and how to read its side.
struct Placement {
    const TriangleMesh* mesh = nullptr;
    const ExactSphere* spheres = nullptr;  ///< set for the sphere geometry (mesh is then null)
    std::uint32_t first_face = 0;
    bool identity = true;
    bool mirrored = false;
    Mat3 to_object;  ///< inverse of the linear part (directions world -> object)
};

/// Our context: Embree passes it back to the filter (the RTCIntersectContext must come first).
struct AllHitsContext {
    RTCIntersectContext ctx;
    const std::vector<Placement>* placements = nullptr;
    Vec3d dir;  ///< the ray direction in world coordinates
    Facing facing = Facing::both;
    std::vector<AllHit>* out = nullptr;
};
static_assert(std::is_standard_layout_v<AllHitsContext>);

void record_all_hits(const RTCFilterFunctionNArguments* args) {
    const auto* c = reinterpret_cast<const AllHitsContext*>(args->context);
    for (unsigned k = 0; k < args->N; ++k) {
        if (args->valid[k] == 0) {
            continue;
        }
        args->valid[k] = 0;  // reject: traversal goes on and reports the next candidate
        const unsigned inst_id = RTCHitN_instID(args->hit, args->N, k, 0);
        const unsigned geom_id = RTCHitN_geomID(args->hit, args->N, k);
        const unsigned prim = RTCHitN_primID(args->hit, args->N, k);
        const Placement& p =
            (*c->placements)[inst_id != RTC_INVALID_GEOMETRY_ID ? inst_id : geom_id];
        const float t = RTCRayN_tfar(args->ray, args->N, k);
        if (p.spheres != nullptr) {
            // Embree's Ng of a sphere hit points outward from the centre: the entry (front) is
            // where the ray runs against it (a tangent counts as front, as in our backends).
            const Vec3d ng(RTCHitN_Ng_x(args->hit, args->N, k), RTCHitN_Ng_y(args->hit, args->N, k),
                           RTCHitN_Ng_z(args->hit, args->N, k));
            const ExactSphere& s = p.spheres[prim];
            const bool front = dot(c->dir, ng) <= 0.0;
            if ((c->facing == Facing::front && !front) || (c->facing == Facing::back && front)) {
                continue;
            }
            c->out->push_back({t, s.face, static_cast<std::uint8_t>(front ? 1 : 0)});
            continue;
        }
        const Face& f = p.mesh->faces[prim];
        const Vec3d a(p.mesh->vertices[f[0]]), b(p.mesh->vertices[f[1]]),
            cc(p.mesh->vertices[f[2]]);
        const Vec3d n = cross(b - a, cc - a);
        const Vec3d d = p.identity ? c->dir : p.to_object * c->dir;
        const bool front = (dot(d, n) < 0.0) != p.mirrored;
        if ((c->facing == Facing::front && !front) || (c->facing == Facing::back && front)) {
            continue;
        }
        c->out->push_back({t, p.first_face + prim, static_cast<std::uint8_t>(front ? 1 : 0)});
    }
}

const char* error_name(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE:
            return "no error";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION:
            return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "unsupported CPU";
        case RTC_ERROR_CANCELLED:
            return "cancelled";
        default:
            return "unknown error";
    }
}

class EmbreeBackend final : public Backend {
    static constexpr std::size_t kPacket = 16;  ///< rays per rtcIntersect16 packet

  public:
    EmbreeBackend(const std::vector<const TriangleMesh*>& meshes,
                  const std::vector<MeshInstance>& instances,
                  const std::vector<ExactSphere>& spheres, ThreadPool& pool) {
        const std::string config = "threads=" + std::to_string(pool.size()) + ",set_affinity=0";
        device_ = rtcNewDevice(config.c_str());
        if (device_ == nullptr) {
            throw ConfigError("Embree: rtcNewDevice failed (" +
                              std::string(error_name(rtcGetDeviceError(nullptr))) + ")");
        }
        rtcSetDeviceErrorFunction(device_, &EmbreeBackend::on_error, this);
        if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED) != 0 ||
            rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED) == 0) {
            release();
            throw ConfigError(
                "Embree was built with backface culling or without filter functions; the "
                "embree backend needs both sides and filter callbacks");
        }
        if (!spheres.empty() &&
            rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_POINT_GEOMETRY_SUPPORTED) == 0) {
            release();
            throw ConfigError(
                "Embree was built without point geometry, which the scene's exact spheres need; "
                "use another backend or spheres with subdivisions");
        }
        try {
            build(meshes, instances, spheres);
        } catch (...) {
            release();
            throw;
        }
    }
    ~EmbreeBackend() override { release(); }
    EmbreeBackend(const EmbreeBackend&) = delete;
    EmbreeBackend& operator=(const EmbreeBackend&) = delete;

    [[nodiscard]] BackendKind kind() const override { return BackendKind::embree; }

    void intersect(const RayBatch& rays, std::size_t begin, std::size_t end, HitBatch& hits,
                   ThreadPool& pool) const override {
        // Packets of kPacket rays aligned on absolute ray indices (i / kPacket), whatever
        // `begin` and the grain, so a ray always shares its packet with the same neighbours and
        // results never depend on the thread count or on how a caller splits its batches.
        if (begin >= end) {
            return;
        }
        const std::size_t first_packet = begin / kPacket;
        const std::size_t packets = (end + kPacket - 1) / kPacket - first_packet;
        const std::size_t grain = std::max<std::size_t>(1, ray_grain(end - begin, pool) / kPacket);
        pool.parallel_for(packets, grain, [&](std::size_t pb, std::size_t pe) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            // Incoherent: Embree 3.13's coherent packet traversal is not watertight (rays
            // through shared edges of closed meshes slip through); this one is.
            ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
            alignas(64) RTCRayHit16 rh;
            init_embree_packet(rh);
            alignas(64) int valid[kPacket];
            for (std::size_t pk = first_packet + pb; pk < first_packet + pe; ++pk) {
                const std::size_t p = std::max(begin, pk * kPacket);
                const std::size_t n = std::min(end, (pk + 1) * kPacket) - p;
                set_embree_packet(rh, valid, rays, p, n);
                rtcIntersect16(valid, scene_, &ctx, &rh);
                for (std::size_t k = 0; k < n; ++k) {
                    store(rh.hit.geomID[k], rh.hit.instID[0][k], rh.hit.primID[k], rh.ray.tfar[k],
                          rh.hit.u[k], rh.hit.v[k], hits, p + k);
                }
            }
        });
    }

    void occluded(const RayBatch& rays, std::size_t begin, std::size_t end,
                  std::vector<std::uint8_t>& occluded, ThreadPool& pool) const override {
        occluded.resize(rays.size());
        pool.parallel_for(end - begin, ray_grain(end - begin, pool),
                          [&](std::size_t b, std::size_t e) {
                              RTCIntersectContext ctx;
                              rtcInitIntersectContext(&ctx);
                              for (std::size_t i = begin + b; i < begin + e; ++i) {
                                  RTCRay r;
                                  set_embree_ray(r, rays, i);
                                  rtcOccluded1(scene_, &ctx, &r);
                                  // A hit sets tfar to -inf.
                                  occluded[i] = r.tfar < 0.0f ? 1 : 0;
                              }
                          });
    }

    void intersect_all(const RayBatch& rays, Facing facing, AllHits& hits,
                       ThreadPool& pool) const override {
        const std::size_t n = rays.size();
        const std::size_t grain = ray_grain(n, pool);
        const std::size_t chunks = (n + grain - 1) / grain;
        std::vector<std::vector<AllHit>> per_chunk(chunks);
        std::vector<std::uint32_t> counts(n, 0);
        pool.parallel_for(n, grain, [&](std::size_t b, std::size_t e) {
            auto& out = per_chunk[b / grain];
            AllHitsContext c;
            rtcInitIntersectContext(&c.ctx);
            c.ctx.filter = &record_all_hits;
            c.placements = &placements_;
            c.facing = facing;
            c.out = &out;
            for (std::size_t i = b; i < e; ++i) {
                const std::size_t before = out.size();
                c.dir = rays.direction(i);
                RTCRayHit rh;
                set_embree_ray(rh.ray, rays, i);
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(scene_, &c.ctx, &rh);
                sort_unique_hits(out, before);
                counts[i] = static_cast<std::uint32_t>(out.size() - before);
            }
        });
        gather_all_hits(per_chunk, counts, hits);
    }

  private:
    static void on_error(void* self, RTCError code, const char* message) {
        auto* backend = static_cast<EmbreeBackend*>(self);
        const std::lock_guard lock(backend->error_mutex_);
        if (backend->error_.empty()) {
            backend->error_ =
                std::string(error_name(code)) + ": " + (message != nullptr ? message : "");
        }
    }
    void check(const char* what) {
        const std::lock_guard lock(error_mutex_);
        if (!error_.empty()) {
            throw ConfigError(std::string("Embree ") + what + ": " + error_);
        }
    }

    void store(unsigned geom_id, unsigned inst_id, unsigned prim_id, float t, float u, float v,
               HitBatch& hits, std::size_t i) const {
        if (geom_id == RTC_INVALID_GEOMETRY_ID) {
            hits.t[i] = std::numeric_limits<float>::infinity();
            hits.face[i] = kNoFace;
            hits.u[i] = hits.v[i] = 0.0f;
            return;
        }
        const Placement& p = placements_[inst_id != RTC_INVALID_GEOMETRY_ID ? inst_id : geom_id];
        hits.t[i] = t;
        if (p.spheres != nullptr) {
            hits.face[i] = p.spheres[prim_id].face;
            hits.u[i] = hits.v[i] = 0.0f;
            return;
        }
        hits.face[i] = p.first_face + prim_id;
        hits.u[i] = u;
        hits.v[i] = v;
    }

    /// The vertex buffer of mesh m: shared when Embree's 16-byte loads stay inside the
    /// allocation, otherwise a padded copy (made once per mesh).
    RTCBuffer vertex_buffer(const TriangleMesh& mesh) {
        const std::size_t bytes = mesh.vertices.size() * sizeof(Vec3f);
        if (mesh.vertices.capacity() > mesh.vertices.size()) {
            // The slack is allocated (if uninitialised): Embree only reads the w lane.
            return rtcNewSharedBuffer(device_, const_cast<Vec3f*>(mesh.vertices.data()),
                                      bytes + sizeof(Vec3f));
        }
        RTCBuffer buffer = rtcNewBuffer(device_, bytes + 4);
        if (buffer != nullptr) {
            void* dst = rtcGetBufferData(buffer);
            std::memcpy(dst, mesh.vertices.data(), bytes);
            std::memset(static_cast<char*>(dst) + bytes, 0, 4);
            ++copied_meshes_;
        }
        return buffer;
    }

    RTCGeometry triangle_geometry(std::size_t m) {
        const TriangleMesh& mesh = *meshes_[m];
        if (vertex_buffers_[m] == nullptr) {
            vertex_buffers_[m] = vertex_buffer(mesh);
            index_buffers_[m] = rtcNewSharedBuffer(device_, const_cast<Face*>(mesh.faces.data()),
                                                   mesh.faces.size() * sizeof(Face));
            check("buffer");
        }
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertex_buffers_[m], 0,
                             sizeof(Vec3f), mesh.vertices.size());
        rtcSetGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, index_buffers_[m], 0,
                             sizeof(Face), mesh.faces.size());
        rtcCommitGeometry(g);
        return g;
    }

    RTCScene new_scene() {
        RTCScene s = rtcNewScene(device_);
        rtcSetSceneFlags(s, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
        scenes_.push_back(s);
        return s;
    }

    /// One sphere-point geometry holding every exact sphere (x, y, z, radius).
    RTCGeometry sphere_geometry(const std::vector<ExactSphere>& spheres) {
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* xyzr = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.size()));
        if (xyzr == nullptr) {
            rtcReleaseGeometry(g);
            check("sphere buffer");
            throw ConfigError("Embree: no buffer for " + std::to_string(spheres.size()) +
                              " spheres");
        }
        for (std::size_t k = 0; k < spheres.size(); ++k) {
            xyzr[4 * k + 0] = spheres[k].center.x;
            xyzr[4 * k + 1] = spheres[k].center.y;
            xyzr[4 * k + 2] = spheres[k].center.z;
            xyzr[4 * k + 3] = spheres[k].radius;
        }
        rtcCommitGeometry(g);
        return g;
    }

    void build(const std::vector<const TriangleMesh*>& meshes,
               const std::vector<MeshInstance>& instances,
               const std::vector<ExactSphere>& spheres) {
        meshes_ = meshes;
        vertex_buffers_.assign(meshes.size(), nullptr);
        index_buffers_.assign(meshes.size(), nullptr);
        std::vector<RTCScene> sub(meshes.size(), nullptr);
        scene_ = new_scene();
        placements_.resize(instances.size());
        for (std::size_t k = 0; k < instances.size(); ++k) {
            const MeshInstance& mi = instances[k];
            const TriangleMesh& mesh = *meshes[mi.mesh];
            Placement& p = placements_[k];
            p.mesh = &mesh;
            p.first_face = mi.first_face;
            p.identity = mi.to_world.is_identity();
            p.mirrored = mi.to_world.determinant() < 0.0;
            if (!p.identity) {
                p.to_object = mi.to_world.inverse().linear;
            }
            if (mesh.faces.empty()) {
                continue;
            }
            RTCGeometry g = nullptr;
            if (p.identity) {
                g = triangle_geometry(mi.mesh);
            } else {
                if (sub[mi.mesh] == nullptr) {
                    sub[mi.mesh] = new_scene();
                    RTCGeometry t = triangle_geometry(mi.mesh);
                    rtcAttachGeometry(sub[mi.mesh], t);
                    rtcReleaseGeometry(t);
                    rtcCommitScene(sub[mi.mesh]);
                }
                g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
                rtcSetGeometryInstancedScene(g, sub[mi.mesh]);
                rtcSetGeometryTimeStepCount(g, 1);
                float xfm[12];  // 3x4 column major: the three columns of the linear part, then t
                for (int c = 0; c < 3; ++c) {
                    for (int r = 0; r < 3; ++r) {
                        xfm[3 * c + r] = static_cast<float>(mi.to_world.linear.m[r][c]);
                    }
                }
                xfm[9] = static_cast<float>(mi.to_world.translation.x);
                xfm[10] = static_cast<float>(mi.to_world.translation.y);
                xfm[11] = static_cast<float>(mi.to_world.translation.z);
                rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
                rtcCommitGeometry(g);
            }
            rtcAttachGeometryByID(scene_, g, static_cast<unsigned>(k));
            rtcReleaseGeometry(g);
            check("geometry");
        }
        if (!spheres.empty()) {
            Placement p;
            p.spheres = spheres.data();
            placements_.push_back(p);
            RTCGeometry g = sphere_geometry(spheres);
            rtcAttachGeometryByID(scene_, g, static_cast<unsigned>(instances.size()));
            rtcReleaseGeometry(g);
            check("spheres");
        }
        rtcCommitScene(scene_);
        check("scene build");
    }

    void release() {
        for (RTCScene s : scenes_) {
            rtcReleaseScene(s);
        }
        scenes_.clear();
        for (auto* list : {&vertex_buffers_, &index_buffers_}) {
            for (RTCBuffer b : *list) {
                if (b != nullptr) {
                    rtcReleaseBuffer(b);
                }
            }
            list->clear();
        }
        if (device_ != nullptr) {
            rtcReleaseDevice(device_);
            device_ = nullptr;
        }
    }

    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<RTCScene> scenes_;  // top scene and per-mesh sub-scenes, released at the end
    std::vector<const TriangleMesh*> meshes_;
    std::vector<RTCBuffer> vertex_buffers_, index_buffers_;
    std::vector<Placement> placements_;  // by top-level geometry ID: instances, then spheres
    std::size_t copied_meshes_ = 0;
    std::mutex error_mutex_;
    std::string error_;
};

}  // namespace

std::unique_ptr<Backend> make_embree_backend(const TriangleMesh& mesh, ThreadPool& pool) {
    MeshInstance only;
    return std::make_unique<EmbreeBackend>(std::vector<const TriangleMesh*>{&mesh},
                                           std::vector<MeshInstance>{only},
                                           std::vector<ExactSphere>{}, pool);
}

std::unique_ptr<Backend> make_embree_backend(const SceneGeometry& geometry, ThreadPool& pool) {
    std::vector<const TriangleMesh*> meshes;
    meshes.reserve(geometry.meshes.size());
    for (const auto& m : geometry.meshes) {
        meshes.push_back(&m);
    }
    return std::make_unique<EmbreeBackend>(meshes, geometry.instances, geometry.spheres, pool);
}

}  // namespace beamtrace::detail
