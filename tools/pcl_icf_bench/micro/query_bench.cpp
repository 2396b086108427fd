// Exact closest-face queries (Embree index and brute force) and closest-point-field lookups,
// per thread, on a 6-face box, a 96-face cylinder and the Stanford bunny (3,851 triangles) or
// the 54,839-triangle dinosaur from ../shared/data. Query points: surface samples displaced
// along a random direction by up to 5 mm, as scan points near a well-posed model are.
//   build/release/bench/pcl_icf_query_bench --benchmark_min_time=1
#include "synthetic/synthetic_models.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/closest_face_query.h>
#include <pcl/icf/registration/distance_field.h>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <random>

namespace {

using namespace pcl::icf;

struct Model {
  std::unique_ptr<FaceMesh> mesh;
  std::unique_ptr<EmbreeClosestFaceIndex> index;
  std::unique_ptr<BruteForceClosestFace> brute;
  std::unique_ptr<ClosestPointField> field;
  std::vector<Eigen::Vector3f> queries;
};

std::unique_ptr<FaceMesh> loadModel(const std::string& name) {
  if (name == "box")
    return std::make_unique<FaceMesh>(FaceMesh::build(synthetic::makeBox(0.14, 0.09, 0.05)));
  if (name == "cylinder")
    return std::make_unique<FaceMesh>(
        FaceMesh::build(synthetic::thesisModel("YellowRoundSalt").mesh));
  const std::string path = std::string(PCL_ICF_SHARED_DATA) + "/meshes/" + name;
  if (!std::filesystem::exists(path))
    return nullptr;
  FaceMeshOptions options;
  if (name.find("parasaurolophus") != std::string::npos)
    options.scale = 1e-3f;  // millimetres
  return std::make_unique<FaceMesh>(FaceMesh::build(io::loadPolygonMesh(path), options));
}

Model& model(const std::string& name) {
  static std::map<std::string, Model> cache;
  auto it = cache.find(name);
  if (it != cache.end())
    return it->second;
  Model m;
  m.mesh = loadModel(name);
  if (m.mesh) {
    m.index = std::make_unique<EmbreeClosestFaceIndex>(*m.mesh);
    m.brute = std::make_unique<BruteForceClosestFace>(*m.mesh);
    m.field = std::make_unique<ClosestPointField>(*m.index);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<float> offset(-0.005f, 0.005f);
    std::normal_distribution<float> g;
    for (const auto& s : sampleSurface(*m.mesh, 1 << 16, 2))
      m.queries.push_back(s.point +
                          offset(rng) * Eigen::Vector3f(g(rng), g(rng), g(rng)).normalized());
  }
  return cache.emplace(name, std::move(m)).first->second;
}

/** The model \a name, or null (the benchmark skipped) when its mesh is not in ../shared/data. */
Model* modelOrSkip(benchmark::State& state, const std::string& name) {
  Model& m = model(name);
  if (m.mesh)
    return &m;
  state.SkipWithError("mesh missing from ../shared/data");
  return nullptr;
}

/** Times \a query on the model's surface-near points in turn, one point per iteration. */
template <typename Query>
void eachQuery(benchmark::State& state, const Model& m, Query query) {
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(query(m.queries[i]));
    i = (i + 1) & (m.queries.size() - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

void exactQueries(benchmark::State& state, const std::string& name, float radius) {
  if (Model* m = modelOrSkip(state, name)) {
    eachQuery(state, *m,
              [&](const Eigen::Vector3f& q) { return m->index->closestFace(q, radius); });
    state.counters["faces"] = static_cast<double>(m->mesh->size());
  }
}

void bruteQueries(benchmark::State& state, const std::string& name) {
  if (Model* m = modelOrSkip(state, name))
    eachQuery(state, *m, [&](const Eigen::Vector3f& q) { return m->brute->closestFace(q, 0.01f); });
}

void fieldLookups(benchmark::State& state, const std::string& name) {
  if (Model* m = modelOrSkip(state, name)) {
    eachQuery(state, *m, [&](const Eigen::Vector3f& q) { return m->field->distance(q); });
    state.counters["cell_mm"] = 1e3 * m->field->cellSize();
  }
}

void fieldBuild(benchmark::State& state, const std::string& name) {
  if (Model* m = modelOrSkip(state, name))
    for (auto _ : state)
      benchmark::DoNotOptimize(ClosestPointField(*m->index));
}

const float kInf = std::numeric_limits<float>::infinity();

}  // namespace

BENCHMARK_CAPTURE(exactQueries, box_r1cm, std::string("box"), 0.01f);
BENCHMARK_CAPTURE(exactQueries, cylinder_r1cm, std::string("cylinder"), 0.01f);
BENCHMARK_CAPTURE(exactQueries, bunny_r1cm, std::string("bunny.ply"), 0.01f);
BENCHMARK_CAPTURE(exactQueries, bunny_unbounded, std::string("bunny.ply"), kInf);
BENCHMARK_CAPTURE(exactQueries, dino55k_r1cm, std::string("parasaurolophus_low_normals2.ply"),
                  0.01f);
BENCHMARK_CAPTURE(bruteQueries, box, std::string("box"));
BENCHMARK_CAPTURE(bruteQueries, cylinder, std::string("cylinder"));
BENCHMARK_CAPTURE(bruteQueries, bunny, std::string("bunny.ply"));
BENCHMARK_CAPTURE(fieldLookups, box, std::string("box"));
BENCHMARK_CAPTURE(fieldLookups, cylinder, std::string("cylinder"));
BENCHMARK_CAPTURE(fieldLookups, bunny, std::string("bunny.ply"));
BENCHMARK_CAPTURE(fieldLookups, dino55k, std::string("parasaurolophus_low_normals2.ply"));
BENCHMARK_CAPTURE(fieldBuild, bunny, std::string("bunny.ply"))->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
