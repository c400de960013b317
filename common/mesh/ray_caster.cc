#include "common/mesh/ray_caster.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>
#include <utility>

#include <embree3/rtcore.h>
#include <Eigen/Geometry>

#include "common/util/error.h"

namespace uw {
namespace {

// Float rounding of centred coordinates is FLT_EPSILON times their size;
// Embree's intersection arithmetic adds a few such roundings. This factor
// keeps shadow rays clear of their own surface with a wide margin while
// staying far below any geometric detail (0.3 mm for a 150 m half-extent).
constexpr double kSurfaceEpsilonUlps = 16.0;

// At grazing incidence the ray-plane intersection is ill-conditioned: a ray
// that Embree sees crossing a triangle can meet that triangle's plane in
// double far from the triangle. The double refinement is kept while it moves
// the hit by less than this many SurfaceEpsilon()s, which holds unless the
// ray is within about 0.01 degrees of grazing; closer, Embree's distance is
// the better answer.
constexpr double kMaxRefinementInEpsilons = 1000.0;

std::string EmbreeErrorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
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
  }
  return "error code " + std::to_string(static_cast<int>(code));
}

void RecordEmbreeError(void* user, RTCError /*code*/, const char* message) {
  *static_cast<std::string*>(user) = message == nullptr ? "" : message;
}

float ToFloatDistance(double distance) {
  return distance < static_cast<double>(FLT_MAX)
             ? static_cast<float>(distance)
             : std::numeric_limits<float>::infinity();
}

// Embree's tfar for Intersect: max_distance widened by the float error of a
// hit distance, so that a hit whose exact distance is within max_distance is
// not lost to rounding; the exact test follows in double.
float WidenedFloatFar(double max_distance, double surface_epsilon) {
  return ToFloatDistance(max_distance + 4.0 * surface_epsilon +
                         4.0 * FLT_EPSILON * std::abs(max_distance));
}

// Embree traces a stream in packets; longer streams only cost memory.
constexpr size_t kMaxStreamSize = 1024;

// Embree marks an occluded ray by tfar = -inf.
bool IsOccluded(const RTCRay& ray) { return ray.tfar < 0.0f; }

}  // namespace

struct RayCaster::Impl {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  // Unit normal of each triangle (zero for zero-area ones, never hit).
  std::vector<Eigen::Vector3d> normals;
  // Area-weighted mean of the normals of the triangles around each vertex.
  std::vector<Eigen::Vector3d> vertex_normals;
  // Subtracted from every position handed to Embree.
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  double surface_epsilon = 0.0;
  std::string last_error;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  void ThrowIfEmbreeFailed(const char* step) const {
    const RTCError code = rtcGetDeviceError(device);
    if (code != RTC_ERROR_NONE) {
      throw ErrorAt("RayCaster: Embree failed to ", step, ": ",
                    EmbreeErrorName(code),
                    last_error.empty() ? "" : " (" + last_error + ")");
    }
  }

  RTCRay EmbreeRay(const Eigen::Vector3d& origin,
                   const Eigen::Vector3d& direction, float tfar) const {
    const Eigen::Vector3f origin_f = (origin - offset).cast<float>();
    RTCRay ray;
    ray.org_x = origin_f.x();
    ray.org_y = origin_f.y();
    ray.org_z = origin_f.z();
    ray.dir_x = static_cast<float>(direction.x());
    ray.dir_y = static_cast<float>(direction.y());
    ray.dir_z = static_cast<float>(direction.z());
    ray.tnear = 0.0f;
    ray.tfar = tfar;
    ray.time = 0.0f;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
    return ray;
  }

  RTCRayHit EmbreeRayHit(const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& direction,
                         double max_distance) const {
    RTCRayHit ray_hit;
    ray_hit.ray = EmbreeRay(origin, direction,
                            WidenedFloatFar(max_distance, surface_epsilon));
    ray_hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    ray_hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return ray_hit;
  }

  // The hit Embree found, recomputed in double against the plane of its
  // triangle.
  std::optional<Hit> Refine(const Eigen::Vector3d& origin,
                            const Eigen::Vector3d& direction,
                            const RTCRayHit& ray_hit,
                            double max_distance) const {
    if (ray_hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
      return std::nullopt;
    }
    const Eigen::Vector3d& a = vertices[triangles[ray_hit.hit.primID](0)];
    const Eigen::Vector3d& normal = normals[ray_hit.hit.primID];
    const double embree_distance = ray_hit.ray.tfar;
    double distance = normal.dot(a - origin) / normal.dot(direction);
    if (!(std::abs(distance - embree_distance) <=
          kMaxRefinementInEpsilons * surface_epsilon)) {
      distance = embree_distance;
    }
    if (distance > max_distance) {
      return std::nullopt;
    }
    Hit hit;
    hit.distance = distance;
    hit.point_in_world = origin + distance * direction;
    hit.normal_in_world = normal;
    hit.triangle_id = ray_hit.hit.primID;
    const Eigen::Vector3i& triangle = triangles[ray_hit.hit.primID];
    const double u = ray_hit.hit.u;
    const double v = ray_hit.hit.v;
    const Eigen::Vector3d shading =
        (1.0 - u - v) * vertex_normals[triangle(0)] +
        u * vertex_normals[triangle(1)] + v * vertex_normals[triangle(2)];
    // Vertex normals that cancel out (a knife edge) give no direction.
    hit.shading_normal_in_world =
        shading.squaredNorm() > 1e-12 ? shading.normalized() : normal;
    return hit;
  }
};

RayCaster::RayCaster(const TriangleMesh& mesh) : impl_(new Impl) {
  if (mesh.triangles.empty()) {
    throw Error("RayCaster: the mesh has no triangles");
  }
  Eigen::Vector3d lower =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d upper = -lower;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      throw ErrorAt("RayCaster: mesh vertex ", i, " is not finite");
    }
    lower = lower.cwiseMin(mesh.vertices[i]);
    upper = upper.cwiseMax(mesh.vertices[i]);
  }
  bool any_area = false;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& triangle = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (triangle(k) < 0 ||
          static_cast<size_t>(triangle(k)) >= mesh.vertices.size()) {
        throw ErrorAt("RayCaster: mesh triangle ", t, " refers to vertex ",
                      triangle(k), " but the mesh has ", mesh.vertices.size(),
                      " vertices");
      }
    }
    const Eigen::Vector3d& a = mesh.vertices[triangle(0)];
    any_area = any_area || (mesh.vertices[triangle(1)] - a)
                                   .cross(mesh.vertices[triangle(2)] - a)
                                   .squaredNorm() > 0.0;
  }
  if (!any_area) {
    throw Error("RayCaster: every triangle of the mesh has zero area");
  }
  impl_->vertices = mesh.vertices;
  impl_->triangles = mesh.triangles;
  impl_->normals.reserve(mesh.triangles.size());
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[triangle(0)];
    impl_->normals.push_back((mesh.vertices[triangle(1)] - a)
                                 .cross(mesh.vertices[triangle(2)] - a)
                                 .normalized());
  }
  // Smooth shading: a surface sampled by small flat triangles and lit by a
  // lamp that moves with the camera would otherwise show every facet as a
  // brightness step that changes from image to image, a false texture that
  // no real seafloor has.
  // Each triangle contributes its normal weighted by its angle at the
  // vertex, which unlike area weighting does not depend on how a surface
  // was split into triangles (Thuermer and Wuethrich 1998).
  impl_->vertex_normals.assign(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& triangle = mesh.triangles[t];
    if (impl_->normals[t].squaredNorm() == 0.0) continue;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& corner = mesh.vertices[triangle(k)];
      const Eigen::Vector3d to_next =
          mesh.vertices[triangle((k + 1) % 3)] - corner;
      const Eigen::Vector3d to_prev =
          mesh.vertices[triangle((k + 2) % 3)] - corner;
      const double angle =
          std::atan2(to_next.cross(to_prev).norm(), to_next.dot(to_prev));
      impl_->vertex_normals[triangle(k)] += angle * impl_->normals[t];
    }
  }
  for (Eigen::Vector3d& normal : impl_->vertex_normals) {
    if (normal.squaredNorm() > 0.0) normal.normalize();
  }
  impl_->offset = 0.5 * (lower + upper);
  const double half_extent = (0.5 * (upper - lower)).cwiseAbs().maxCoeff();
  impl_->surface_epsilon =
      kSurfaceEpsilonUlps * FLT_EPSILON * std::max(1.0, half_extent);

  impl_->device = rtcNewDevice(nullptr);
  if (impl_->device == nullptr) {
    throw ErrorAt("RayCaster: Embree could not create a device: ",
                  EmbreeErrorName(rtcGetDeviceError(nullptr)));
  }
  rtcSetDeviceErrorFunction(impl_->device, RecordEmbreeError,
                            &impl_->last_error);
  impl_->scene = rtcNewScene(impl_->device);
  impl_->ThrowIfEmbreeFailed("create a scene");
  // Robust traversal: a ray through an edge shared by two triangles must hit
  // one of them, or the seafloor gets pinholes of background colour.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  // A survey renders thousands of images of one static mesh.
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);

  RTCGeometry geometry =
      rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  impl_->ThrowIfEmbreeFailed("create a triangle geometry");
  auto* vertices_f = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
      mesh.vertices.size()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
      3 * sizeof(uint32_t), mesh.triangles.size()));
  if (vertices_f == nullptr || indices == nullptr) {
    rtcReleaseGeometry(geometry);
    impl_->ThrowIfEmbreeFailed("allocate the mesh buffers");
    throw Error("RayCaster: Embree could not allocate the mesh buffers");
  }
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3f centred =
        (mesh.vertices[i] - impl_->offset).cast<float>();
    vertices_f[3 * i + 0] = centred.x();
    vertices_f[3 * i + 1] = centred.y();
    vertices_f[3 * i + 2] = centred.z();
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& triangle = mesh.triangles[t];
    const bool has_area = impl_->normals[t].squaredNorm() > 0.0;
    // Rounding to float can give a zero-area triangle a sliver of area, and
    // its hit then has no plane to refine against; collapsing it to one
    // vertex makes it unhittable for Embree as well.
    for (int k = 0; k < 3; ++k) {
      indices[3 * t + k] =
          static_cast<uint32_t>(has_area ? triangle(k) : triangle(0));
    }
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  impl_->ThrowIfEmbreeFailed("build the scene");
  // Queries may run on many threads; none may write the error message.
  rtcSetDeviceErrorFunction(impl_->device, nullptr, nullptr);
}

RayCaster::~RayCaster() = default;
RayCaster::RayCaster(RayCaster&& other) noexcept = default;
RayCaster& RayCaster::operator=(RayCaster&& other) noexcept = default;

std::optional<RayCaster::Hit> RayCaster::Intersect(
    const Eigen::Vector3d& origin, const Eigen::Vector3d& unit_direction,
    double max_distance) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit ray_hit = impl_->EmbreeRayHit(origin, unit_direction, max_distance);
  rtcIntersect1(impl_->scene, &context, &ray_hit);
  return impl_->Refine(origin, unit_direction, ray_hit, max_distance);
}

void RayCaster::IntersectMany(const std::vector<Ray>& rays,
                              std::vector<std::optional<Hit>>* hits,
                              double max_distance) const {
  hits->resize(rays.size());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  std::vector<RTCRayHit> ray_hits;
  for (size_t begin = 0; begin < rays.size(); begin += kMaxStreamSize) {
    const size_t count = std::min(kMaxStreamSize, rays.size() - begin);
    ray_hits.resize(count);
    for (size_t k = 0; k < count; ++k) {
      const Ray& ray = rays[begin + k];
      ray_hits[k] =
          impl_->EmbreeRayHit(ray.origin, ray.direction, max_distance);
    }
    rtcIntersect1M(impl_->scene, &context, ray_hits.data(),
                   static_cast<unsigned int>(count), sizeof(RTCRayHit));
    for (size_t k = 0; k < count; ++k) {
      const Ray& ray = rays[begin + k];
      (*hits)[begin + k] =
          impl_->Refine(ray.origin, ray.direction, ray_hits[k], max_distance);
    }
  }
}

bool RayCaster::Occluded(const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& unit_direction,
                         double max_distance) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray =
      impl_->EmbreeRay(origin, unit_direction, ToFloatDistance(max_distance));
  rtcOccluded1(impl_->scene, &context, &ray);
  return IsOccluded(ray);
}

void RayCaster::OccludedMany(const std::vector<Ray>& rays,
                             const std::vector<double>& max_distances,
                             std::vector<bool>* occluded) const {
  if (max_distances.size() != rays.size()) {
    throw ErrorAt("RayCaster::OccludedMany: ", rays.size(), " rays but ",
                  max_distances.size(), " distances");
  }
  occluded->resize(rays.size());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  std::vector<RTCRay> embree_rays;
  for (size_t begin = 0; begin < rays.size(); begin += kMaxStreamSize) {
    const size_t count = std::min(kMaxStreamSize, rays.size() - begin);
    embree_rays.resize(count);
    for (size_t k = 0; k < count; ++k) {
      const Ray& ray = rays[begin + k];
      embree_rays[k] = impl_->EmbreeRay(
          ray.origin, ray.direction, ToFloatDistance(max_distances[begin + k]));
    }
    rtcOccluded1M(impl_->scene, &context, embree_rays.data(),
                  static_cast<unsigned int>(count), sizeof(RTCRay));
    for (size_t k = 0; k < count; ++k) {
      (*occluded)[begin + k] = IsOccluded(embree_rays[k]);
    }
  }
}

double RayCaster::SurfaceEpsilon() const { return impl_->surface_epsilon; }

}  // namespace uw
