/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * pcl_icf.Tracker: pcl::icf::tracking::ObjectTracker over numpy frames (python/README.md,
 * "Tracking"). The C++ tracker holds the models' IcfModel pointers; the Python objects keep them
 * alive.
 */
#include "tracker.h"

#include "arrays.h"
#include "model.h"
#include "params.h"
#include "results.h"

#include <pybind11/stl.h>

#include <pcl/icf/tracking/object_tracker.h>

#include <memory>
#include <string>
#include <utility>

namespace pcl_icf_python {

namespace trk = pcl::icf::tracking;
using namespace pybind11::literals;

namespace {

py::object trackNamespace(const trk::ObjectTrack& o, int index) {
  py::dict d;
  d["object"] = index;
  d["name"] = o.name;
  d["state"] = trk::toString(o.state);
  d["pose"] = o.pose ? matrixArray(o.pose->matrix().cast<double>()).cast<py::object>()
                     : py::none().cast<py::object>();
  d["confidence"] = o.confidence;
  d["verification"] = verificationDict(o.verification);
  d["refined"] = o.refined;
  d["refine_confidence"] = o.refine_confidence;
  d["refine_message"] = o.refine_message;
  d["searched"] = o.searched;
  d["refine_points"] = o.refine_points;
  d["refine_iterations"] = o.refine_iterations;
  d["refine_ms"] = o.refine_ms;
  d["verify_ms"] = o.verify_ms;
  d["search_ms"] = o.search_ms;
  d["reacquire_tried"] = o.reacquire_tried;
  d["reacquired"] = o.reacquired;
  d["reacquire_points"] = o.reacquire_points;
  d["reacquire_ms"] = o.reacquire_ms;
  d["frames_lost"] = o.frames_lost;
  d["message"] = o.message;
  return makeNamespace(d);
}

/** The tracker and the Python models it follows (kept alive with it). */
class Tracker {
 public:
  explicit Tracker(const py::kwargs& kwargs) {
    trk::TrackerParams params;
    applyTrackerKwargs(params, kwargs);
    tracker_ = std::make_unique<trk::ObjectTracker>(params);
  }

  int addObject(const std::shared_ptr<Model>& model, const std::string& name) {
    if (!model)
      throw py::type_error("add_object(): model must be a pcl_icf.Model");
    models_.push_back(model);
    return tracker_->addObject(model->icf, name);
  }

  void setPose(int object, const py::handle& pose) {
    if (object < 0 || static_cast<std::size_t>(object) >= tracker_->size())
      throw py::index_error("object: " + std::to_string(object) + " is not an added object (0.." +
                            std::to_string(static_cast<long>(tracker_->size()) - 1) + ")");
    tracker_->setPose(object, rigidPose(pose, "pose"));
  }

  py::object track(const py::array& xyz, const py::object& rgb, const py::object& camera) {
    auto cloud = sceneCloud(xyz, rgb, "scene_xyz", "rgb");
    if (!camera.is_none()) {
      const Eigen::Isometry3f c = rigidPose(camera, "camera");
      cloud.sensor_origin_.head<3>() = c.translation();
      cloud.sensor_origin_[3] = 0.f;
      cloud.sensor_orientation_ = Eigen::Quaternionf(c.linear());
    }
    trk::TrackedFrame frame;
    {
      py::gil_scoped_release release;
      frame = tracker_->track(cloud);
    }
    py::list objects;
    for (std::size_t k = 0; k < frame.objects.size(); ++k)
      objects.append(trackNamespace(frame.objects[k], static_cast<int>(k)));
    return makeNamespace(py::dict("frame"_a = frame.index, "objects"_a = objects,
                                  "image_ms"_a = frame.image_ms, "total_ms"_a = frame.total_ms));
  }

  void reset() { tracker_->reset(); }
  std::size_t size() const { return tracker_->size(); }

 private:
  std::unique_ptr<trk::ObjectTracker> tracker_;
  std::vector<std::shared_ptr<Model>> models_;
};

}  // namespace

void bindTracker(py::module_& m) {
  static const std::string init_doc =
      "Tracker(**params): every localize() keyword (search and verification) and the "
      "tracker's own; see tracker_defaults()." +
      keywordDoc(true);
  py::class_<Tracker>(m, "Tracker",
                      "Follows objects over consecutive frames of one camera "
                      "(pcl::icf::tracking::ObjectTracker): a search on the first frame and "
                      "after a loss, a refinement from the last pose otherwise, each verified "
                      "against the depth.")
      .def(py::init<const py::kwargs&>(), init_doc.c_str())
      .def("add_object", &Tracker::addObject, py::arg("model"), py::arg("name"),
           "Follow model under name; returns its index in every frame's objects.")
      .def("set_pose", &Tracker::setPose, py::arg("object"), py::arg("pose"),
           "Start object from pose (4x4 model -> camera) instead of a search.")
      .def("track", &Tracker::track, py::arg("scene_xyz"), py::arg("rgb") = py::none(),
           py::arg("camera") = py::none(),
           "track(scene_xyz, rgb=None, camera=None): one frame ((N, 3) or (H, W, 3), metres). "
           "Returns a namespace with frame, objects (in add_object order: name, state "
           "'searching'|'found'|'tracking'|'lost'|'re-found', pose (4x4 model -> scene) or None, "
           "confidence, verification, timings) and total_ms.")
      .def("reset", &Tracker::reset, "Forget every pose: the next frame searches again.")
      .def("__len__", &Tracker::size);
  m.def("tracker_defaults", &trackerDefaults,
        "The keyword parameters of Tracker() with their C++ defaults.");
}

}  // namespace pcl_icf_python
