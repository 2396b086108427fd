// Error of the closest-point field against exact distances, within 3 cm of the surface
// (where scoring happens), on the benchmark meshes: median, 99th percentile and maximum.
//   build/release/bench/pcl_icf_field_error
#include "synthetic/synthetic_models.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/distance_field.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>

using namespace pcl::icf;

namespace {

void report(const std::string& name, const FaceMesh& mesh) {
  const EmbreeClosestFaceIndex index(mesh);
  const ClosestPointField field(index);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  const float band = 0.03f;
  const Eigen::Vector3f lo = mesh.boundsMin() - Eigen::Vector3f::Constant(band);
  const Eigen::Vector3f hi = mesh.boundsMax() + Eigen::Vector3f::Constant(band);
  std::vector<float> errors;
  while (errors.size() < 200000) {
    const Eigen::Vector3f p = lo + Eigen::Vector3f(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
    const float exact = index.closestFace(p).distance;
    if (exact <= band)
      errors.push_back(std::abs(field.distance(p) - exact));
  }
  std::sort(errors.begin(), errors.end());
  std::printf("| %s | %zu | %.2f | %.1f%% | %.4f | %.3f | %.3f |\n", name.c_str(), mesh.size(),
              1e3 * field.cellSize(), 100.0 * field.medialCellRatio(),
              1e3 * errors[errors.size() / 2], 1e3 * errors[errors.size() * 99 / 100],
              1e3 * errors.back());
}

}  // namespace

int main() {
  std::printf(
      "| mesh | faces | cell (mm) | medial cells | median error (mm) | p99 (mm) | max (mm) "
      "|\n|---|---|---|---|---|---|---|\n");
  report("box 14x9x5 cm", FaceMesh::build(synthetic::makeBox(0.14, 0.09, 0.05)));
  report("cylinder (YellowRoundSalt)",
         FaceMesh::build(synthetic::thesisModel("YellowRoundSalt").mesh));
  const std::string bunny = std::string(PCL_ICF_SHARED_DATA) + "/meshes/bunny.ply";
  if (std::filesystem::exists(bunny))
    report("Stanford bunny", FaceMesh::build(io::loadPolygonMesh(bunny)));
  return 0;
}
