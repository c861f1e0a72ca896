#include "beamtrace/render/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/png_writer.hpp"

namespace beamtrace {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::size_t kGrain = 1024;

/// The visible surface point of one pixel ray.
struct Surface {
    Vec3d position_m;
    Vec3d normal;     ///< unit, facing the camera
    Vec3d view;       ///< unit, from the point towards the camera
    double t = kInf;  ///< +inf: the ray saw nothing
    double albedo = 0.0;
    Vec3d color{1, 1, 1};
    std::uint32_t material = 0;
    std::int32_t part = -1;
};

/// The sky's colour along direction `d` (RenderConfig::sky).
Vec3d sky_color(const Vec3d& d) {
    const double up = std::clamp(d.z, 0.0, 1.0);
    const Vec3d horizon{0.85, 0.9, 1.0}, zenith{0.3, 0.5, 0.9};
    return horizon + (zenith - horizon) * std::sqrt(up);
}

/// Offset of shadow-ray origins along the normal: clears float triangles and rounding.
double surface_offset(const Vec3d& p) {
    const double m = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    return 2e-5 * (1.0 + m);
}

}  // namespace

Renderer::Renderer(const RenderScene& scene, ThreadPool& pool, BackendKind backend)
    : scene_(scene), pool_(pool) {
    scene_.check();
    if (!scene_.mesh.faces.empty()) {
        backend_ = make_backend(backend, scene_.mesh, pool_);
    }
}

RenderImage Renderer::render(const RenderConfig& config) const {
    const Camera camera(config.camera);
    if (config.batch_pixels == 0) {
        throw ConfigError("render: batch_pixels must be positive");
    }
    for (const auto& l : config.lights) {
        if (!(l.intensity >= 0.0) || !std::isfinite(l.intensity) ||
            (l.kind == LightKind::directional && !(std::fabs(length(l.direction) - 1.0) < 1e-6))) {
            throw ConfigError(
                "render: light intensities must be finite and >= 0, directions unit vectors");
        }
    }
    RenderImage img;
    img.width = camera.width();
    img.height = camera.height();
    const std::size_t n_pixels = camera.pixel_count();
    img.radiance.assign(n_pixels, static_cast<float>(config.background));
    img.depth_m.assign(n_pixels, std::numeric_limits<float>::infinity());
    img.part.assign(n_pixels, -1);
    img.color.assign(3 * n_pixels, 1.0F);
    const auto width = static_cast<std::size_t>(img.width);

    RayBatch rays;
    HitBatch hits;
    std::vector<Surface> surf;
    std::vector<double> radiance;
    RayBatch shadow;
    std::vector<std::uint32_t> shadow_pixel;
    std::vector<std::uint8_t> occluded;
    for (std::size_t start = 0; start < n_pixels; start += config.batch_pixels) {
        const std::size_t n = std::min(config.batch_pixels, n_pixels - start);
        rays.resize(n);
        pool_.parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                const std::size_t px = start + i;
                Vec3d o, d;
                camera.pixel_ray(static_cast<int>(px % width), static_cast<int>(px / width), o, d);
                rays.set(i, o, d);
            }
        });
        hits.resize(n);
        if (backend_) {
            backend_->intersect(rays, 0, n, hits, pool_);
        }
        // Nearest of the triangle hit and the exact primitives, and its surface properties.
        surf.assign(n, Surface{});
        radiance.assign(n, config.background);
        pool_.parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                const Vec3d o = rays.origin(i), d = rays.direction(i);
                double best = hits.hit(i) ? static_cast<double>(hits.t[i]) : kInf;
                int kind = hits.hit(i) ? 0 : -1;  // 0 mesh, 1 sphere, 2 plane
                std::size_t which = 0;
                for (std::size_t k = 0; k < scene_.spheres.size(); ++k) {
                    if (const auto t = intersect_sphere(o, d, scene_.spheres[k].sphere, 0.0, best);
                        t && *t < best) {
                        best = *t;
                        kind = 1;
                        which = k;
                    }
                }
                for (std::size_t k = 0; k < scene_.planes.size(); ++k) {
                    if (const auto t = intersect_plane(o, d, scene_.planes[k].plane, 0.0, best);
                        t && *t < best) {
                        best = *t;
                        kind = 2;
                        which = k;
                    }
                }
                if (kind < 0) {
                    if (config.sky) {
                        surf[i].color = sky_color(d);
                        radiance[i] = 1.0;
                    }
                    continue;
                }
                Surface& s = surf[i];
                s.t = best;
                s.view = -d;
                PatternFrame frame;  // meshes: a solid (the pattern in scene coordinates)
                if (kind == 0) {
                    const std::uint32_t f = hits.face[i];
                    const Face& face = scene_.mesh.faces[f];
                    const Vec3d a(scene_.mesh.vertices[face[0]]);
                    const Vec3d ab = Vec3d(scene_.mesh.vertices[face[1]]) - a;
                    const Vec3d ac = Vec3d(scene_.mesh.vertices[face[2]]) - a;
                    s.position_m = a + ab * static_cast<double>(hits.u[i]) +
                                   ac * static_cast<double>(hits.v[i]);
                    s.normal = normalize(cross(ab, ac));
                    s.material = scene_.face_material[f];
                    s.part = static_cast<std::int32_t>(scene_.face_part[f]);
                } else if (kind == 1) {
                    const RenderSphere& sp = scene_.spheres[which];
                    s.position_m = o + d * best;
                    s.normal = (s.position_m - sp.sphere.center_m) * (1.0 / sp.sphere.radius_m);
                    s.material = sp.material;
                    s.part = static_cast<std::int32_t>(sp.part);
                    frame =
                        PatternFrame::sphere(sp.sphere.center_m, sp.sphere.radius_m, sp.attitude);
                } else {
                    const RenderPlane& pl = scene_.planes[which];
                    s.position_m = o + d * best;
                    s.normal = pl.plane.normal;
                    s.material = pl.material;
                    s.part = static_cast<std::int32_t>(pl.part);
                    frame =
                        PatternFrame::plane(pl.plane.point_m, pl.plane.u_axis, pl.plane.w_axis());
                }
                const Material& m = scene_.materials[s.material];
                s.albedo = albedo(m, frame, s.position_m);
                s.color = pattern_color(m.pattern, frame, s.position_m, m.color);
                if (dot(s.normal, d) > 0.0) {
                    s.normal = -s.normal;  // two-sided: shade the side the camera sees
                }
                radiance[i] = config.ambient * s.albedo;
            }
        });
        // One batch of occlusion rays per light, then the light's share of every lit pixel.
        for (const Light& light : config.lights) {
            shadow_pixel.clear();
            for (std::size_t i = 0; i < n; ++i) {
                if (std::isfinite(surf[i].t)) {
                    shadow_pixel.push_back(static_cast<std::uint32_t>(i));
                }
            }
            const std::size_t m = shadow_pixel.size();
            shadow.resize(m);
            pool_.parallel_for(m, kGrain, [&](std::size_t b, std::size_t e) {
                for (std::size_t j = b; j < e; ++j) {
                    const Surface& s = surf[shadow_pixel[j]];
                    const Vec3d o = s.position_m + s.normal * surface_offset(s.position_m);
                    if (light.kind == LightKind::directional) {
                        shadow.set(j, o, light.direction, 0.0, kInf);
                    } else {
                        const Vec3d to = light.position_m - o;
                        const double dist = length(to);
                        shadow.set(j, o, dist > 0.0 ? to * (1.0 / dist) : Vec3d{0, 0, 1}, 0.0,
                                   dist);
                    }
                }
            });
            occluded.assign(m, 0);
            if (config.shadows && backend_ && m > 0) {
                backend_->occluded(shadow, 0, m, occluded, pool_);
            }
            pool_.parallel_for(m, kGrain, [&](std::size_t b, std::size_t e) {
                for (std::size_t j = b; j < e; ++j) {
                    const std::size_t i = shadow_pixel[j];
                    const Surface& s = surf[i];
                    // Shade with the direction and distance from the surface point itself (the
                    // shadow ray starts a little above it).
                    const Vec3d to_light = light.position_m - s.position_m;
                    const Vec3d l = light.kind == LightKind::directional ? light.direction
                                                                         : normalize(to_light);
                    const double cos_i = dot(s.normal, l);
                    if (!(cos_i > 0.0) || occluded[j] != 0) {
                        continue;
                    }
                    const Vec3d o = shadow.origin(j), ls = shadow.direction(j);
                    const double tmax = shadow.tmax[j];
                    if (config.shadows) {
                        bool blocked = false;
                        for (const auto& sp : scene_.spheres) {
                            const auto iv = intersect_sphere_line(o, ls, sp.sphere);
                            if (iv && iv->t_exit > 0.0 && iv->t_enter < tmax) {
                                blocked = true;
                                break;
                            }
                        }
                        for (std::size_t k = 0; !blocked && k < scene_.planes.size(); ++k) {
                            blocked = intersect_plane(o, ls, scene_.planes[k].plane, 0.0, tmax)
                                          .has_value();
                        }
                        if (blocked) {
                            continue;
                        }
                    }
                    const double irradiance = light.kind == LightKind::directional
                                                  ? light.intensity
                                                  : light.intensity / dot(to_light, to_light);
                    const Material& mat = scene_.materials[s.material];
                    radiance[i] +=
                        s.albedo * irradiance *
                        reflectance(config.brdf, cos_i, dot(s.normal, s.view), dot(s.view, l),
                                    mat.specular_weight, mat.specular_exponent);
                }
            });
        }
        for (std::size_t i = 0; i < n; ++i) {
            img.radiance[start + i] = static_cast<float>(radiance[i]);
            img.depth_m[start + i] = static_cast<float>(surf[i].t);
            img.part[start + i] = surf[i].part;
            img.color[3 * (start + i)] = static_cast<float>(surf[i].color.x);
            img.color[3 * (start + i) + 1] = static_cast<float>(surf[i].color.y);
            img.color[3 * (start + i) + 2] = static_cast<float>(surf[i].color.z);
        }
    }
    return img;
}

std::vector<double> Renderer::thickness(const CameraConfig& config) const {
    const Camera camera(config);
    const std::size_t n = camera.pixel_count();
    const auto width = static_cast<std::size_t>(camera.width());
    RayBatch rays;
    rays.resize(n);
    std::vector<double> out(n, 0.0);
    pool_.parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
            Vec3d o, d;
            camera.pixel_ray(static_cast<int>(i % width), static_cast<int>(i / width), o, d);
            rays.set(i, o, d);
            for (const auto& sp : scene_.spheres) {
                out[i] += sphere_chord(o, d, sp.sphere, 0.0, kInf);
            }
        }
    });
    if (backend_) {
        AllHits all;
        backend_->intersect_all(rays, Facing::both, all, pool_);
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t k = all.offsets[i]; k < all.offsets[i + 1]; ++k) {
                const double t = all.t[k];
                out[i] += all.front[k] != 0 ? -t : t;
            }
        }
    }
    return out;
}

std::vector<std::uint8_t> to_rgb8(const RenderImage& image, double exposure, double gamma) {
    if (!(exposure > 0.0) || !(gamma > 0.0)) {
        throw ConfigError("render: exposure and gamma must be positive");
    }
    const bool tinted = image.color.size() == 3 * image.radiance.size();
    std::vector<std::uint8_t> rgb(image.radiance.size() * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        const double tint = tinted ? static_cast<double>(image.color[i]) : 1.0;
        double v =
            std::clamp(exposure * static_cast<double>(image.radiance[i / 3]) * tint, 0.0, 1.0);
        if (gamma != 1.0) {
            v = std::pow(v, 1.0 / gamma);
        }
        rgb[i] = static_cast<std::uint8_t>(std::lround(255.0 * v));
    }
    return rgb;
}

void write_render_png(const std::filesystem::path& path, const RenderImage& image, double exposure,
                      double gamma) {
    const auto rgb = to_rgb8(image, exposure, gamma);
    write_png_rgb8(path, image.width, image.height, rgb);
}

}  // namespace beamtrace
