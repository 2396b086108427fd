/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The Python module pcl_icf (python/README.md): numpy in, pose out. A thin shell over
 * pcl::icf::localization::localizeObject, pcl::icf::estimatePose, the tracker (tracker.cpp) and
 * the io readers: arrays are read where they lie (any strides), the GIL is released while the
 * C++ works, and the C++ validate() messages reach Python as ValueError.
 */
#include "arrays.h"
#include "model.h"
#include "params.h"
#include "results.h"
#include "tracker.h"

#include <pybind11/stl.h>

#include <pcl/conversions.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/localization/objects_localizer.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/model_file.h>

#include <chrono>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <utility>

namespace pcl_icf_python {

namespace localization = pcl::icf::localization;
using namespace pybind11::literals;

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

/** Diagonal of the finite vertices' bounding box (the tool's --model-units auto rule). */
double meshExtent(const pcl::PolygonMesh& mesh) {
  pcl::PointCloud<pcl::PointXYZ> v;
  pcl::fromPCLPointCloud2(mesh.cloud, v);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f hi = -lo;
  for (const auto& p : v)
    if (p.getVector3fMap().allFinite()) {
      lo = lo.cwiseMin(p.getVector3fMap());
      hi = hi.cwiseMax(p.getVector3fMap());
    }
  return (hi - lo).allFinite() ? static_cast<double>((hi - lo).norm()) : 0.0;
}

/** The tool's rule (tools/pcl_icf_tool/tool_run.cpp): a mesh spanning more than 2 units is in
 * millimetres. */
constexpr double kModelMillimetreExtent = 2.0;

/** The units a mesh is read in: "m" or "mm" as asked, or by the tool's rule for "auto". */
std::string modelUnits(const pcl::PolygonMesh& mesh, const std::string& units) {
  if (units != "m" && units != "mm" && units != "auto")
    throw py::value_error("units: '" + units + "' is not m, mm or auto");
  if (units == "auto")
    return meshExtent(mesh) > kModelMillimetreExtent ? "mm" : "m";
  return units;
}

pcl::icf::IcfModelParams modelParams(const std::string& units) {
  pcl::icf::IcfModelParams params;
  params.mesh.scale = units == "mm" ? 1e-3f : 1.f;
  return params;
}

/** The model of \a mesh, through the prepared-model cache \a cache_folder ("" none); a cache
 * that cannot be used is a Python warning, the model is right either way. */
std::shared_ptr<Model> buildModel(pcl::PolygonMesh mesh, const std::string& units,
                                  const std::string& cache_folder = "") {
  auto model = std::make_shared<Model>();
  model->vertices = static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height;
  model->units = modelUnits(mesh, units);
  model->mesh = std::move(mesh);
  pcl::icf::CachedModel cached;
  {
    py::gil_scoped_release release;
    cached = pcl::icf::buildModelCached(model->mesh, modelParams(model->units), cache_folder);
  }
  if (!cached.warning.empty() &&
      PyErr_WarnEx(PyExc_RuntimeWarning, ("prepared-model cache: " + cached.warning).c_str(), 1) <
          0)
    throw py::error_already_set();  // warnings turned into errors
  model->icf = cached.model;
  model->source = cached.from_cache ? "cache" : "built";
  return model;
}

/** Model.from_file: a mesh file (through the cache when \a cache), or a prepared-model file
 * (pcl_icf_tool --prepare, Model.save) read as it is. */
std::shared_ptr<Model> modelFromFile(const std::string& path, const std::string& units,
                                     bool cache) {
  if (pcl::icf::isModelFile(path)) {
    auto model = std::make_shared<Model>();
    {
      py::gil_scoped_release release;
      model->mesh = pcl::icf::readModelFileMesh(path);
    }
    model->vertices = static_cast<std::size_t>(model->mesh.cloud.width) * model->mesh.cloud.height;
    model->units = modelUnits(model->mesh, units);
    py::gil_scoped_release release;
    model->icf = pcl::icf::readModelFile(path, model->mesh, modelParams(model->units));
    model->source = "prepared file";
    return model;
  }
  pcl::PolygonMesh mesh;
  {
    py::gil_scoped_release release;
    mesh = pcl::icf::io::loadPolygonMesh(path);
  }
  if (mesh.polygons.empty())
    throw py::value_error(path + ": the mesh has no faces (a point cloud is not a model)");
  return buildModel(std::move(mesh), units, cache ? pcl::icf::defaultModelCacheFolder() : "");
}

/** The registration's own measures at the final pose (pose_verification.h). */
py::dict qualityDict(const pcl::icf::PoseQuality& q) {
  return py::dict(
      py::arg("thesis_score") = q.thesis_score, py::arg("inlier_ratio") = q.inlier_ratio,
      py::arg("rmse") = q.rmse, py::arg("surface_coverage") = q.surface_coverage,
      py::arg("far_points") = q.far_points, py::arg("inliers") = q.inliers,
      py::arg("visible_samples") = q.visible_samples, py::arg("seen_through") = q.seen_through);
}

py::object clusterNamespace(const localization::ClusterLocalization& c, int index) {
  py::dict d;
  d["cluster"] = index;
  d["source_cluster"] = c.source_cluster;
  d["prescore"] = c.prescore;
  d["points"] = c.indices.indices.size();
  d["indices"] = py::array_t<int>(static_cast<py::ssize_t>(c.indices.indices.size()),
                                  c.indices.indices.data());
  d["pose"] = matrixArray(c.icf.object_pose.cast<double>());
  d["confidence"] = c.verification.confidence;
  d["score"] = c.score;
  d["accepted"] = c.accepted;
  d["reason"] = c.reason;
  d["method"] = c.icf.method;
  d["icf_status"] = pcl::icf::toString(c.icf.status);
  d["fallback_ran"] = c.icf.fallback_ran;
  d["quality"] = qualityDict(c.icf.quality);
  d["verification"] = verificationDict(c.verification);
  d["gate_far_points"] = c.gate_far_points;
  d["colour_similarity"] =
      c.colour_similarity ? py::cast(*c.colour_similarity) : py::none().cast<py::object>();
  d["turned"] = c.turned;
  d["ambiguous"] = !c.alternatives.empty();
  py::list alternatives;
  for (const auto& a : c.alternatives) {
    py::dict alt;
    alt["pose"] = matrixArray(a.object_pose.matrix().cast<double>());
    alt["confidence"] = a.verification.confidence;
    alt["residual"] = a.verification.residual;
    alt["turn_axis_model"] = py::make_tuple(a.axis.x(), a.axis.y(), a.axis.z());
    alt["turn_deg"] = a.turn_deg;
    alt["origin_offset"] = a.translation_offset;
    alt["verification"] = verificationDict(a.verification);
    alternatives.append(makeNamespace(alt));
  }
  d["alternatives"] = alternatives;
  d["time_ms"] = c.icf.time_ms;
  return makeNamespace(d);
}

py::object localizationNamespace(const localization::Localization& loc, double call_ms) {
  py::list clusters;
  for (std::size_t k = 0; k < loc.clusters.size(); ++k)
    clusters.append(clusterNamespace(loc.clusters[k], static_cast<int>(k)));
  py::list instances;
  for (int k : loc.instances)
    instances.append(clusters[static_cast<std::size_t>(k)]);
  py::dict d;
  d["status"] = localization::toString(loc.status);
  d["message"] = loc.message;
  d["found"] = loc.best >= 0;
  d["instances"] = instances;
  d["best"] =
      loc.best >= 0 ? clusters[static_cast<std::size_t>(loc.best)] : py::none().cast<py::object>();
  d["clusters"] = clusters;
  d["camera_pose"] = matrixArray(loc.camera_pose.matrix().cast<double>());
  py::dict timing;
  timing["segmentation_ms"] = loc.segmentation_ms;
  timing["registration_ms"] = loc.registration_ms;
  timing["total_ms"] = loc.total_ms;
  timing["call_ms"] = call_ms;
  d["timing"] = timing;
  return makeNamespace(d);
}

/** localize(scene_xyz[, rgb], model, camera=None, **params). */
py::object localize(const py::args& args, const py::kwargs& kwargs) {
  const auto start = std::chrono::steady_clock::now();
  py::dict rest;
  py::object xyz, rgb = py::none(), model, camera = py::none();
  if (args.size() < 1 || args.size() > 3)
    throw py::type_error(
        "localize(scene_xyz[, rgb], model, camera=None, **params) takes 1 to 3 "
        "positional arguments, got " +
        std::to_string(args.size()));
  xyz = args[0];
  if (args.size() == 2)
    model = args[1];
  if (args.size() == 3) {
    rgb = args[1];
    model = args[2];
  }
  for (const auto& item : kwargs) {
    const auto name = item.first.cast<std::string>();
    if (name == "rgb")
      rgb = py::reinterpret_borrow<py::object>(item.second);
    else if (name == "model")
      model = py::reinterpret_borrow<py::object>(item.second);
    else if (name == "camera")
      camera = py::reinterpret_borrow<py::object>(item.second);
    else if (name == "scene_xyz")
      throw py::type_error("localize(): scene_xyz is positional");
    else
      rest[item.first] = item.second;
  }
  if (!model || model.is_none() || !py::isinstance<Model>(model))
    throw py::type_error("localize(): model must be a pcl_icf.Model");
  if (!py::isinstance<py::array>(xyz))
    throw py::value_error("scene_xyz: expected a numpy array of shape (N, 3) or (H, W, 3)");
  localization::LocalizerParams params;
  applyLocalizerKwargs(params, rest.cast<py::kwargs>());
  if (!camera.is_none())
    params.camera_pose = rigidPose(camera, "camera");
  const auto cloud = sceneCloud(xyz.cast<py::array>(), rgb, "scene_xyz", "rgb");
  const auto icf = model.cast<const Model&>().icf;
  localization::Localization loc;
  {
    py::gil_scoped_release release;
    loc = localization::localizeObject(cloud, *icf, params);
  }
  return localizationNamespace(loc, msSince(start));
}

/** localize_many(scene_xyz, models, rgb=None, camera=None, names=None, counts=None, **params). */
py::object localizeMany(const py::array& xyz, const py::list& models, const py::object& rgb,
                        const py::object& camera, const py::object& names, const py::object& counts,
                        const py::kwargs& kwargs) {
  const auto start = std::chrono::steady_clock::now();
  if (models.empty())
    throw py::value_error("localize_many(): models is empty");
  std::vector<localization::ObjectQuery> queries;
  for (std::size_t k = 0; k < models.size(); ++k) {
    if (!py::isinstance<Model>(models[k]))
      throw py::type_error("localize_many(): models[" + std::to_string(k) +
                           "] is not a pcl_icf.Model");
    queries.push_back({models[k].cast<const Model&>().icf, "object " + std::to_string(k), 1});
  }
  const auto perObject = [&](const py::object& list, const char* what, auto set) {
    if (list.is_none())
      return;
    const auto values = list.cast<py::list>();
    if (values.size() != queries.size())
      throw py::value_error(std::string("localize_many(): ") + what + " needs one entry per model");
    for (std::size_t k = 0; k < queries.size(); ++k)
      set(queries[k], values[k]);
  };
  perObject(names, "names", [](localization::ObjectQuery& q, const py::handle& v) {
    q.name = v.cast<std::string>();
  });
  perObject(counts, "counts", [](localization::ObjectQuery& q, const py::handle& v) {
    q.max_instances = v.cast<int>();
    if (q.max_instances < 1)
      throw py::value_error("localize_many(): every count must be at least 1");
  });
  localization::LocalizerParams params;
  applyLocalizerKwargs(params, kwargs);
  if (!camera.is_none())
    params.camera_pose = rigidPose(camera, "camera");
  const auto cloud = sceneCloud(xyz, rgb, "scene_xyz", "rgb");
  localization::ObjectsLocalization all;
  {
    py::gil_scoped_release release;
    all = localization::localizeObjects(cloud, queries, params);
  }
  const double call_ms = msSince(start);
  py::list objects;
  for (const auto& loc : all.objects)
    objects.append(localizationNamespace(loc, call_ms));
  py::list instances;
  for (const auto& i : all.instances)
    instances.append(py::make_tuple(i.object, objects[static_cast<std::size_t>(i.object)].attr(
                                                  "clusters")[py::int_(i.hypothesis)]));
  py::dict timing;
  timing["scene_ms"] = all.scene_ms;
  timing["selection_ms"] = all.selection_ms;
  timing["total_ms"] = all.total_ms;
  timing["call_ms"] = call_ms;
  return makeNamespace(py::dict("status"_a = localization::toString(all.status),
                                "message"_a = all.message, "found"_a = !all.instances.empty(),
                                "objects"_a = objects, "instances"_a = instances,
                                "timing"_a = timing));
}

py::object estimatePose(const py::array& cluster_xyz, const Model& model, const py::object& guess,
                        const py::object& camera, const py::kwargs& kwargs) {
  pcl::icf::IcfParams params;
  applyIcfKwargs(params, kwargs);
  const auto points = finitePoints(cluster_xyz, "cluster_xyz");
  Eigen::Vector3f camera_position = Eigen::Vector3f::Zero();
  if (!camera.is_none()) {
    const auto c = camera.cast<std::vector<double>>();
    if (c.size() != 3 || !Eigen::Vector3d(c[0], c[1], c[2]).allFinite())
      throw py::value_error("camera: expected the camera's position (x, y, z), finite");
    camera_position = Eigen::Vector3d(c[0], c[1], c[2]).cast<float>();
  }
  pcl::icf::PoseEstimateOptions options;
  if (!guess.is_none())
    options.guess = rigidPose(guess, "guess").inverse();
  pcl::icf::IcfResult r;
  {
    py::gil_scoped_release release;
    r = pcl::icf::estimatePose(*model.icf, points, camera_position, params, options);
  }
  return makeNamespace(py::dict("status"_a = pcl::icf::toString(r.status),
                                "accepted"_a = r.accepted(),
                                "pose"_a = matrixArray(r.object_pose.cast<double>()),
                                "scene_to_model"_a = matrixArray(r.scene_to_model.cast<double>()),
                                "quality"_a = qualityDict(r.quality), "method"_a = r.method,
                                "refinement_iterations"_a = r.refinement_iterations,
                                "refinement_converged"_a = r.refinement_converged,
                                "points"_a = r.points, "search_score"_a = r.search_score,
                                "fallback_ran"_a = r.fallback_ran, "time_ms"_a = r.time_ms));
}

/** load_scene(path): xyz and rgb as views into the loaded cloud (no copy). */
py::object loadScene(const std::string& path) {
  auto holder = std::make_unique<pcl::PointCloud<pcl::PointXYZRGBA>::Ptr>();
  pcl::icf::io::SceneFileInfo info;
  {
    py::gil_scoped_release release;
    *holder = pcl::icf::io::loadSceneCloud(path, &info);
  }
  const auto& cloud = **holder;
  Eigen::Isometry3f camera = Eigen::Isometry3f::Identity();
  camera.translation() = cloud.sensor_origin_.head<3>();
  camera.linear() = cloud.sensor_orientation_.normalized().toRotationMatrix();
  auto* base = reinterpret_cast<const std::uint8_t*>(cloud.data());
  const auto h = static_cast<py::ssize_t>(cloud.height);
  const auto w = static_cast<py::ssize_t>(cloud.width);
  constexpr auto step = static_cast<py::ssize_t>(sizeof(pcl::PointXYZRGBA));
  py::capsule owner(holder.release(), [](void* p) {
    delete static_cast<pcl::PointCloud<pcl::PointXYZRGBA>::Ptr*>(p);
  });
  const bool organized = cloud.height > 1;
  const std::vector<py::ssize_t> shape =
      organized ? std::vector<py::ssize_t>{h, w, 3} : std::vector<py::ssize_t>{h * w, 3};
  const std::vector<py::ssize_t> xyz_strides =
      organized ? std::vector<py::ssize_t>{w * step, step, 4} : std::vector<py::ssize_t>{step, 4};
  // PointXYZRGBA stores b, g, r, a: r first, channels walked backwards.
  const std::vector<py::ssize_t> rgb_strides =
      organized ? std::vector<py::ssize_t>{w * step, step, -1} : std::vector<py::ssize_t>{step, -1};
  const std::size_t r_offset = offsetof(pcl::PointXYZRGBA, rgba) + 2;
  py::array xyz(py::dtype::of<float>(), shape, xyz_strides, base, owner);
  py::array rgb(py::dtype::of<std::uint8_t>(), shape, rgb_strides, base + r_offset, owner);
  // Read-only views: the cloud is shared by both.
  py::detail::array_proxy(xyz.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  py::detail::array_proxy(rgb.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return makeNamespace(py::dict(
      "xyz"_a = xyz, "rgb"_a = rgb, "camera_pose"_a = matrixArray(camera.matrix().cast<double>()),
      "format"_a = info.format, "has_colour"_a = info.has_colour, "organized"_a = info.organized,
      "points"_a = info.points, "finite_points"_a = info.finite_points));
}

}  // namespace

}  // namespace pcl_icf_python

PYBIND11_MODULE(pcl_icf, m) {
  namespace pip = pcl_icf_python;
  namespace py = pybind11;
  using pip::Model;
  m.doc() =
      "pcl_icf: find the 6D pose of a CAD mesh in a depth scan (Iterative Closest Face).\n"
      "Lengths in metres; poses are 4x4 model -> scene matrices (numpy float64).";

  py::register_exception<pcl::icf::io::FileError>(m, "FileError", PyExc_OSError);
  py::register_exception<pcl::icf::ModelFileError>(m, "ModelFileError", PyExc_ValueError);

  py::class_<Model, std::shared_ptr<Model>>(m, "Model",
                                            "A CAD mesh prepared for pose estimation (IcfModel).")
      .def(
          py::init([](const py::array& vertices, const py::array& faces, const std::string& units) {
            return pip::buildModel(pip::polygonMesh(vertices, faces), units);
          }),
          py::arg("vertices"), py::arg("faces"), py::arg("units") = "m",
          "Model(vertices (V, 3) float, faces (F, 3) int, units='m'|'mm'|'auto')")
      .def_static("from_file", &pip::modelFromFile, py::arg("path"), py::arg("units") = "auto",
                  py::arg("cache") = true,
                  "Load .ply/.obj/.stl/.vtk, or a prepared model (.icfmodel: pcl_icf_tool "
                  "--prepare, Model.save); units 'auto' (the tool's rule: millimetres when the "
                  "mesh spans more than 2 units), 'm' or 'mm'. cache: read and write the "
                  "prepared-model cache ($XDG_CACHE_HOME/pcl_icf, else ~/.cache/pcl_icf), as "
                  "the tool does; a cache that cannot be used is a RuntimeWarning.")
      .def(
          "save",
          [](const Model& model, const std::string& path) {
            py::gil_scoped_release release;
            pcl::icf::writeModelFile(
                *model.icf, model.mesh,
                pcl::icf::preparationKey(model.mesh, pip::modelParams(model.units)), path);
          },
          py::arg("path"),
          "save(path): write the prepared model with its mesh (a .icfmodel file that "
          "Model.from_file and pcl_icf_tool read in milliseconds).")
      .def_property_readonly("source", [](const Model& model) { return model.source; })
      .def_property_readonly("units", [](const Model& model) { return model.units; })
      .def_property_readonly("faces", [](const Model& model) { return model.icf->mesh().size(); })
      .def_property_readonly("vertices", [](const Model& model) { return model.vertices; })
      .def_property_readonly("radius", [](const Model& model) { return model.icf->radius(); })
      .def("__repr__", [](const Model& model) {
        return "<pcl_icf.Model " + std::to_string(model.icf->mesh().size()) + " faces, radius " +
               std::to_string(model.icf->radius()) + " m, read in " + model.units + ">";
      });

  static const std::string localize_doc =
      "localize(scene_xyz[, rgb], model, camera=None, **params)\n\n"
      "scene_xyz: (N, 3) or organized (H, W, 3) float32/float64, metres, NaN for no depth;\n"
      "rgb: uint8 of the same shape (optional); camera: 4x4 camera -> scene pose (default:\n"
      "identity); mesh_accuracy: how far the mesh may lie from the object (metres);\n"
      "params: see localize_defaults(). Returns a namespace with status, message,\n"
      "found, instances (best first), best, clusters, camera_pose and timing; each instance\n"
      "has pose (4x4), confidence, verification terms, quality, alternatives, time_ms." +
      pip::keywordDoc(false);
  m.def("localize", &pip::localize, localize_doc.c_str());
  m.def("localize_many", &pip::localizeMany, py::arg("scene_xyz"), py::arg("models"),
        py::arg("rgb") = py::none(), py::arg("camera") = py::none(), py::arg("names") = py::none(),
        py::arg("counts") = py::none(),
        "localize_many(scene_xyz, models, rgb=None, camera=None, names=None, counts=None,\n"
        "**params): every model of the list found in one pass (localizeObjects): the scene's\n"
        "work once, one selection in which each scene point explains one pose at most (a pose\n"
        "that loses its points to another model's is refused: 'explained better by NAME\n"
        "instance K'). names: what refusals call each model (default 'object K'); counts: at\n"
        "most that many instances of each (default 1). params as localize(). Returns a\n"
        "namespace with status, message, found, objects (one localize() result per model),\n"
        "instances (every accepted (object index, instance), best first) and timing.");
  m.def("estimate_pose", &pip::estimatePose, py::arg("cluster_xyz"), py::arg("model"),
        py::arg("guess") = py::none(), py::arg("camera") = py::none(),
        "estimate_pose(cluster_xyz, model, guess=None, camera=None, **params): the model's pose "
        "in one cluster (pcl::icf::estimatePose). guess: a 4x4 model -> scene start pose; "
        "camera: the sensor's position (x, y, z), default the origin.");
  m.def("load_scene", &pip::loadScene, py::arg("path"),
        "Read a .pcd/.ply/.xyz scene with the project's reader: xyz and rgb are read-only views "
        "of the loaded cloud; camera_pose is the file's VIEWPOINT.");
  pip::bindTracker(m);
  m.def("localize_defaults", &pip::localizerDefaults,
        "The keyword parameters of localize() with their C++ defaults.");
  m.def("estimate_pose_defaults", &pip::icfDefaults,
        "The keyword parameters of estimate_pose() with their C++ defaults.");
  m.def("fields", &pip::localizerFieldList,
        "The registered keywords of localize() (the tool's --set and --list-fields, the "
        "bench's overrides): a dict each with name, kind, min, max, choices, default, tuning "
        "(a calibration constant) and doc.");
}
