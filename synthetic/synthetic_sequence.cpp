#include "synthetic/synthetic_sequence.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace synthetic {

Eigen::Vector3d SequenceObject::placement(int frame) const {
  const double f = static_cast<double>(frame);
  Eigen::Vector3d p = start + f * velocity;
  if (sway_period > 0.0)
    p += std::sin(2.0 * 3.14159265358979323846 * f / sway_period) * sway;
  return p;
}

bool SequenceObject::present(int frame) const {
  return frame < absent_from || frame >= absent_until;
}

SequenceFrame renderSequenceFrame(const SequenceSpec& spec, int frame) {
  if (frame < 0 || frame >= spec.frames)
    throw std::invalid_argument("renderSequenceFrame: frame " + std::to_string(frame) +
                                " outside [0, " + std::to_string(spec.frames) + ")");
  std::vector<SyntheticModel> models;
  std::vector<Eigen::Vector3d> places;
  std::vector<int> label(spec.objects.size(), -1);  // per spec object, in the scene
  for (std::size_t i = 0; i < spec.objects.size(); ++i) {
    const SequenceObject& o = spec.objects[i];
    if (!o.present(frame))
      continue;
    models.push_back(o.model);
    places.push_back(o.placement(frame));
    label[i] = static_cast<int>(models.size());
  }
  ScanNoise noise = spec.noise;
  noise.seed += static_cast<std::uint64_t>(frame);
  SequenceFrame out;
  out.scene = makeTabletopScene(models, places, spec.intrinsics, noise, spec.camera_height,
                                spec.camera_tilt_deg);
  for (std::size_t i = 0; i < spec.objects.size(); ++i) {
    const SequenceObject& o = spec.objects[i];
    const Eigen::Isometry3d pose =
        out.scene.table_to_camera * standOnTable(o.model.mesh, o.placement(frame));
    out.present.push_back(label[i] > 0);
    out.poses.push_back(pose);
    double visible = 0.0;
    if (label[i] > 0) {
      SceneObject alone;
      alone.mesh = &o.model.mesh;
      alone.pose = pose;
      visible = visibleShare(out.scene.scan, label[i], alone, spec.intrinsics) *
                inViewShare(alone, spec.intrinsics);
    }
    out.visible.push_back(visible);
  }
  return out;
}

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
