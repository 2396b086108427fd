/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_render.h"

#include <pcl/common/io.h>
#include <pcl/conversions.h>
#include <pcl/visualization/pcl_visualizer.h>

#include <vtkCamera.h>
#include <vtkCommand.h>
#include <vtkDataSet.h>
#include <vtkImageData.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPointPicker.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>
#include <Eigen/Geometry>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace pcl_icf_tool {

namespace {

constexpr const char* kUnderXvfb = "PCL_ICF_TOOL_UNDER_XVFB";
/** Set by the tests: --view clicks once in the middle of the window and closes. */
constexpr const char* kViewSelfTest = "PCL_ICF_TOOL_VIEW_SELFTEST";

/** The VTK camera that looks like the sensor, and the window size. */
struct CameraSetup {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d focal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d up = -Eigen::Vector3d::UnitY();
  double view_angle_deg = 45.0;  ///< vertical
  double window_center_x = 0.0;  ///< VTK's SetWindowCenter: principal point offset
  double window_center_y = 0.0;
  int width = 800;
  int height = 600;
  int point_size = 2;
};

/** Least squares fit of u = f a + c. Returns false when degenerate. */
bool fitLine(const std::vector<double>& a, const std::vector<double>& u, double& f, double& c) {
  const double n = static_cast<double>(a.size());
  if (a.size() < 10)
    return false;
  double sa = 0, su = 0, saa = 0, sau = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sa += a[i];
    su += u[i];
    saa += a[i] * a[i];
    sau += a[i] * u[i];
  }
  const double den = n * saa - sa * sa;
  if (!(std::abs(den) > 1e-12))
    return false;
  f = (n * sau - sa * su) / den;
  c = (su - f * sa) / n;
  return std::isfinite(f) && std::isfinite(c) && f > 0.0;
}

CameraSetup cameraFor(const pcl::PointCloud<pcl::PointXYZRGBA>& scene, int want_width,
                      int want_height) {
  CameraSetup cam;
  const Eigen::Isometry3d sensor =
      Eigen::Translation3d(scene.sensor_origin_.head<3>().cast<double>()) *
      scene.sensor_orientation_.cast<double>().normalized();
  const Eigen::Isometry3d to_sensor = sensor.inverse();
  cam.position = sensor.translation();
  cam.focal = sensor * Eigen::Vector3d::UnitZ();
  cam.up = sensor.linear() * -Eigen::Vector3d::UnitY();

  // Viewing-ray slopes of the points in front of the sensor.
  std::vector<double> ax, ay, pu, pv;
  std::size_t finite = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < scene.size(); ++i) {
    const auto& q = scene[i];
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
      continue;
    ++finite;
    const Eigen::Vector3d p = to_sensor * Eigen::Vector3d(q.x, q.y, q.z);
    centroid += p;
    if (p.z() <= 0.0)
      continue;
    ax.push_back(p.x() / p.z());
    ay.push_back(p.y() / p.z());
    if (scene.height > 1) {
      pu.push_back(static_cast<double>(i % scene.width));
      pv.push_back(static_cast<double>(i / scene.width));
    }
  }
  if (finite == 0)
    return cam;
  centroid /= static_cast<double>(finite);

  double fx = 0, cx = 0, fy = 0, cy = 0;
  int w = 0, h = 0;
  if (scene.height > 1 && fitLine(ax, pu, fx, cx) && fitLine(ay, pv, fy, cy)) {
    // An organized cloud: the picture has the camera's own geometry.
    w = static_cast<int>(scene.width);
    h = static_cast<int>(scene.height);
  } else if (ax.size() * 2 >= finite) {
    // Unorganized, mostly in front of the sensor: a pinhole that frames every point.
    w = 800;
    h = 600;
    auto range = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      const std::size_t lo = v.size() / 200, hi = v.size() - 1 - v.size() / 200;
      return std::make_pair(v[lo], v[hi]);
    };
    const auto [xmin, xmax] = range(ax);
    const auto [ymin, ymax] = range(ay);
    fx = fy = 0.85 * std::min(w / std::max(xmax - xmin, 1e-6), h / std::max(ymax - ymin, 1e-6));
    cx = 0.5 * (w - 1) - fx * 0.5 * (xmin + xmax);
    cy = 0.5 * (h - 1) - fy * 0.5 * (ymin + ymax);
    // Points big enough to close the gaps of a sparse cloud: about the mean spacing of the
    // points over the area they cover (half their bounding box).
    const double area = 0.5 * fx * (xmax - xmin) * fy * (ymax - ymin);
    const double spacing = std::sqrt(area / static_cast<double>(ax.size()));
    cam.point_size = std::clamp(static_cast<int>(std::ceil(spacing)), 2, 8);
  } else {
    // Not a camera-frame cloud: look at its centroid from behind along the sensor's z.
    double radius = 0.0;
    for (const auto& q : scene)
      if (std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z))
        radius = std::max(radius, (to_sensor * Eigen::Vector3d(q.x, q.y, q.z) - centroid).norm());
    cam.focal = sensor * centroid;
    cam.position = sensor * (centroid - 2.5 * std::max(radius, 1e-3) * Eigen::Vector3d::UnitZ());
    cam.view_angle_deg = 30.0;
    cam.width = want_width > 0 ? want_width : 800;
    cam.height = want_height > 0 ? want_height : 600;
    return cam;
  }

  // Scale the camera's image to about 640 pixels wide (or to the size asked for).
  const int k = std::max(1, static_cast<int>(std::lround(640.0 / w)));
  cam.width = want_width > 0 ? want_width : w * k;
  cam.height = want_height > 0 ? want_height : h * k;
  if (scene.height > 1)
    cam.point_size = std::max(1, static_cast<int>(std::ceil(static_cast<double>(cam.width) / w)));
  cam.view_angle_deg = 2.0 * std::atan(0.5 * h / fy) * 180.0 / M_PI;
  // VTK's window centre is minus the principal point's position in normalized coordinates
  // (screen x = sensor x, screen up = sensor -y).
  cam.window_center_x = 1.0 - 2.0 * (cx + 0.5) / w;
  cam.window_center_y = 2.0 * (cy + 0.5) / h - 1.0;
  return cam;
}

/** Adds the scene, the model and the caption, and places the camera. */
void populate(pcl::visualization::PCLVisualizer& viewer, const RenderInput& input,
              const CameraSetup& cam) {
  viewer.setBackgroundColor(0.0, 0.0, 0.0);
  viewer.setShowFPS(false);
  auto rgb = pcl::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>();
  pcl::copyPointCloud(*input.scene, *rgb);
  if (input.scene_has_colour) {
    pcl::visualization::PointCloudColorHandlerRGBField<pcl::PointXYZRGB> colour(rgb);
    viewer.addPointCloud<pcl::PointXYZRGB>(rgb, colour, "scene");
  } else {
    pcl::visualization::PointCloudColorHandlerGenericField<pcl::PointXYZRGB> depth(rgb, "z");
    viewer.addPointCloud<pcl::PointXYZRGB>(rgb, depth, "scene");
  }
  viewer.setPointCloudRenderingProperties(pcl::visualization::PCL_VISUALIZER_POINT_SIZE,
                                          cam.point_size, "scene");
  for (std::size_t k = 0; k < input.models.size(); ++k) {
    // Pull the model 1% of its distance towards the camera: the picture's geometry is
    // unchanged (points slide along their rays) but the model is drawn over the scan's own
    // points of its surface, which the sensor's noise scatters in front of and behind it.
    const DrawnModel& model = input.models[k];
    pcl::PointCloud<pcl::PointXYZ> vertices;
    pcl::fromPCLPointCloud2(model.mesh.cloud, vertices);
    const Eigen::Vector3f eye = cam.position.cast<float>();
    for (auto& v : vertices)
      v.getVector3fMap() = eye + 0.99f * (v.getVector3fMap() - eye);
    pcl::PolygonMesh front;
    pcl::toPCLPointCloud2(vertices, front.cloud);
    front.polygons = model.mesh.polygons;
    const std::string id = "model" + std::to_string(k);
    viewer.addPolygonMesh(front, id);
    const Eigen::Vector3f& c = model.colour;
    viewer.setPointCloudRenderingProperties(pcl::visualization::PCL_VISUALIZER_COLOR, c.x(), c.y(),
                                            c.z(), id);
    viewer.setPointCloudRenderingProperties(pcl::visualization::PCL_VISUALIZER_OPACITY, 0.75, id);
  }
  viewer.setSize(cam.width, cam.height);
  vtkRenderer* renderer = viewer.getRendererCollection()->GetFirstRenderer();
  // Text in white or its legend colour with a dark shadow, readable over light and dark scenes.
  const auto addLine = [&](const std::string& line, const Eigen::Vector3f& colour, int y) {
    auto text = vtkSmartPointer<vtkTextActor>::New();
    text->SetInput(line.c_str());
    vtkTextProperty* style = text->GetTextProperty();
    style->SetFontSize(14);
    style->SetColor(colour.x(), colour.y(), colour.z());
    style->ShadowOn();
    text->SetDisplayPosition(6, y);
    renderer->AddActor2D(text);
  };
  if (!input.caption.empty())
    addLine(input.caption, Eigen::Vector3f::Ones(), cam.height - 22);
  for (std::size_t k = 0; k < input.legend.size(); ++k)
    addLine(input.legend[k].text, input.legend[k].colour,
            6 + 18 * static_cast<int>(input.legend.size() - 1 - k));
  viewer.setCameraPosition(cam.position.x(), cam.position.y(), cam.position.z(), cam.focal.x(),
                           cam.focal.y(), cam.focal.z(), cam.up.x(), cam.up.y(), cam.up.z());
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetViewAngle(cam.view_angle_deg);
  camera->SetWindowCenter(cam.window_center_x, cam.window_center_y);
  renderer->ResetCameraClippingRange();
}

}  // namespace

Eigen::Vector3f objectColour(std::size_t k) {
  static const Eigen::Vector3f kColours[] = {
      {0.1f, 1.0f, 0.2f},  {1.0f, 0.55f, 0.1f},  {1.0f, 0.2f, 0.85f},  {0.1f, 0.85f, 1.0f},
      {1.0f, 0.95f, 0.1f}, {1.0f, 0.15f, 0.15f}, {0.35f, 0.45f, 1.0f}, {0.7f, 1.0f, 0.6f}};
  return kColours[k % (sizeof(kColours) / sizeof(kColours[0]))];
}

std::string ensureDisplayOrReexec(int argc, char** argv, bool need_render) {
  if (!need_render || haveDisplay())
    return "";
  if (std::getenv(kUnderXvfb))
    return "no usable X display even under xvfb-run (is Xvfb working?)";
  // Find xvfb-run on the PATH.
  const char* path = std::getenv("PATH");
  std::string found;
  std::string dirs = path ? path : "/usr/bin:/bin";
  for (std::size_t start = 0; start <= dirs.size();) {
    const std::size_t colon = std::min(dirs.find(':', start), dirs.size());
    const std::string candidate = dirs.substr(start, colon - start) + "/xvfb-run";
    if (colon > start && ::access(candidate.c_str(), X_OK) == 0) {
      found = candidate;
      break;
    }
    start = colon + 1;
  }
  if (found.empty())
    return "--render needs an X display: DISPLAY is unset and xvfb-run is not installed "
           "(Debian: apt-get install xvfb xauth)";
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n <= 0)
    return "cannot find this program's path to restart it under xvfb-run";
  self[n] = '\0';
  ::setenv(kUnderXvfb, "1", 1);
  std::vector<char*> args;
  std::string a0 = found, a1 = "-a", a2 = "-s", a3 = "-screen 0 1920x1080x24 -noreset";
  args.push_back(a0.data());
  args.push_back(a1.data());
  args.push_back(a2.data());
  args.push_back(a3.data());
  args.push_back(self);
  for (int i = 1; i < argc; ++i)
    args.push_back(argv[i]);
  args.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execv(found.c_str(), args.data());
  return "could not run xvfb-run (" + found + ")";
}

void renderPng(const RenderInput& input, const std::string& png_path) {
  if (!haveDisplay())
    throw std::runtime_error("no X display to render with (run under xvfb-run)");
  const CameraSetup cam = cameraFor(*input.scene, input.width, input.height);
  pcl::visualization::PCLVisualizer viewer("pcl_icf_tool", false);
  vtkRenderWindow* window = viewer.getRenderWindow();
  window->SetOffScreenRendering(1);
  populate(viewer, input, cam);
  window->Render();

  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* image = grab->GetOutput();
  int dims[3] = {0, 0, 0};
  image->GetDimensions(dims);
  auto* pixels = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  if (!pixels || dims[0] <= 0 || dims[1] <= 0)
    throw std::runtime_error("rendering produced no image");
  const vtkIdType count = pixels->GetNumberOfTuples();
  const int comps = pixels->GetNumberOfComponents();
  const unsigned char* data = pixels->GetPointer(0);
  vtkIdType differing = 0;
  for (vtkIdType i = 1; i < count; ++i)
    differing += !std::equal(data, data + comps, data + i * comps);
  if (differing < count / 1000)
    throw std::runtime_error("the rendered picture is blank (OpenGL could not draw)");

  auto writer = vtkSmartPointer<vtkPNGWriter>::New();
  writer->SetFileName(png_path.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0)
    throw std::runtime_error("could not write the PNG " + png_path);
}

void runViewer(const RenderInput& input) {
  if (!haveDisplay())
    throw std::runtime_error("--view needs a display (DISPLAY is unset or cannot be opened)");
  const CameraSetup cam = cameraFor(*input.scene, input.width, input.height);
  pcl::visualization::PCLVisualizer viewer("pcl_icf_tool");
  populate(viewer, input, cam);
  viewer.addText("click a point to print its coordinates; q closes", 8, 8, 12, 0.8, 0.8, 0.8,
                 "help");
  vtkRenderer* renderer = viewer.getRendererCollection()->GetFirstRenderer();

  auto print = [](float x, float y, float z) {
    std::printf("point %.6g %.6g %.6g\n", x, y, z);
    std::fflush(stdout);
  };
  // Shift+click: PCL's own point picking.
  viewer.registerPointPickingCallback([&](const pcl::visualization::PointPickingEvent& e) {
    float x, y, z;
    e.getPoint(x, y, z);
    print(x, y, z);
  });
  // A plain click (press and release without moving), as in the thesis's tool.
  int press_x = -1, press_y = -1;
  viewer.registerMouseCallback([&](const pcl::visualization::MouseEvent& e) {
    if (e.getButton() != pcl::visualization::MouseEvent::LeftButton)
      return;
    if (e.getType() == pcl::visualization::MouseEvent::MouseButtonPress) {
      press_x = static_cast<int>(e.getX());
      press_y = static_cast<int>(e.getY());
      return;
    }
    if (e.getType() != pcl::visualization::MouseEvent::MouseButtonRelease ||
        (e.getKeyboardModifiers() & pcl::visualization::INTERACTOR_KB_MOD_SHIFT) ||
        std::abs(static_cast<int>(e.getX()) - press_x) +
                std::abs(static_cast<int>(e.getY()) - press_y) >
            2)
      return;
    auto picker = vtkSmartPointer<vtkPointPicker>::New();
    picker->SetTolerance(0.005);
    if (picker->Pick(static_cast<double>(e.getX()), static_cast<double>(e.getY()), 0.0, renderer) &&
        picker->GetPointId() >= 0 && picker->GetDataSet()) {
      double p[3];
      picker->GetDataSet()->GetPoint(picker->GetPointId(), p);
      print(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
    }
  });
  if (std::getenv(kViewSelfTest)) {
    // For the tests: one click in the middle of the window, then close.
    viewer.spinOnce(10, true);
    vtkRenderWindowInteractor* interactor = viewer.getRenderWindow()->GetInteractor();
    interactor->SetEventInformation(cam.width / 2, cam.height / 2, 0, 0);
    interactor->InvokeEvent(vtkCommand::LeftButtonPressEvent);
    interactor->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
    return;
  }
  while (!viewer.wasStopped())
    viewer.spinOnce(50);
}

}  // namespace pcl_icf_tool
