/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/closest_face_query.h>

#include <embree3/rtcore.h>

#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace {

/** Per-query state handed to Embree's point-query callback. */
struct QueryState {
  const FaceMesh* mesh;
  ClosestFace* best;
  float best_sq;
};

void faceBounds(const RTCBoundsFunctionArguments* args) {
  const auto* mesh = static_cast<const FaceMesh*>(args->geometryUserPtr);
  const std::size_t f = args->primID;
  Eigen::Vector3f lo = mesh->faceVertex(f, 0), hi = lo;
  for (std::uint32_t k = 1; k < mesh->faces()[f].count; ++k) {
    lo = lo.cwiseMin(mesh->faceVertex(f, k));
    hi = hi.cwiseMax(mesh->faceVertex(f, k));
  }
  RTCBounds* b = args->bounds_o;
  b->lower_x = lo.x();
  b->lower_y = lo.y();
  b->lower_z = lo.z();
  b->upper_x = hi.x();
  b->upper_y = hi.y();
  b->upper_z = hi.z();
}

bool closestFaceCallback(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<QueryState*>(args->userPtr);
  const Eigen::Vector3f p(args->query->x, args->query->y, args->query->z);
  const ClosestPointOnFace<float> c = closestPointOnMeshFace(*state->mesh, args->primID, p);
  if (!(c.squared_distance < state->best_sq))
    return false;
  state->best_sq = c.squared_distance;
  ClosestFace& best = *state->best;
  best.point = c.point;
  best.face = static_cast<int>(args->primID);
  best.feature = c.feature;
  best.feature_index = c.feature_index;
  args->query->radius = std::sqrt(c.squared_distance);
  return true;
}

void throwOnDeviceError(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree failed to ") + what + " (error " +
                             std::to_string(static_cast<int>(error)) + ")");
}

}  // namespace

struct EmbreeClosestFaceIndex::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene)
      rtcReleaseScene(scene);
    if (device)
      rtcReleaseDevice(device);
  }
};

EmbreeClosestFaceIndex::EmbreeClosestFaceIndex(const FaceMesh& mesh)
    : ClosestFaceQuery(mesh), impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device)
    throw std::runtime_error("Embree failed to create a device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(mesh.size()));
  rtcSetGeometryUserData(geometry, const_cast<FaceMesh*>(&mesh));
  rtcSetGeometryBoundsFunction(geometry, faceBounds, nullptr);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  throwOnDeviceError(impl_->device, "build the face BVH");
}

EmbreeClosestFaceIndex::~EmbreeClosestFaceIndex() = default;

ClosestFace EmbreeClosestFaceIndex::closestFace(const Eigen::Vector3f& p,
                                                float max_distance) const {
  ClosestFace best;
  if (!p.allFinite() || !(max_distance >= 0.f))
    return best;
  QueryState state{&mesh_, &best, max_distance * max_distance};
  RTCPointQuery query;
  query.x = p.x();
  query.y = p.y();
  query.z = p.z();
  query.radius = max_distance;
  query.time = 0.f;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &query, &context, closestFaceCallback, &state);
  if (best.found())
    best.distance = std::sqrt(state.best_sq);
  return best;
}

ClosestFaceQuery::Ptr makeClosestFaceIndex(const FaceMesh& mesh) {
  return std::make_shared<EmbreeClosestFaceIndex>(mesh);
}

}  // namespace icf
}  // namespace pcl
