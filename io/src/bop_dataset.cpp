/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// BOP datasets: the JSON files through nlohmann::json, the PNGs through libpng (PCL's own PNG
// support is disabled in Debian's build; VTK's reader crashes on a truncated file). What is ours is
// the checking: every key looked up by name, every value's type and size checked, the file and key
// named in the error.
#include <pcl/icf/io/bop_dataset.h>

#include <nlohmann/json.hpp>

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>

namespace pcl {
namespace icf {
namespace io {

namespace {

using json = nlohmann::json;

json readJson(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw FileError(path + ": cannot be read");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw FileError(path + ": not valid JSON (" + e.what() + ")");
  }
}

/** A JSON value checked as it is read: the file and the key path in every error. */
class Value {
 public:
  Value(const json& j, std::string path, std::string key)
      : j_(j), path_(std::move(path)), key_(std::move(key)) {}
  [[noreturn]] void fail(const std::string& why) const {
    throw FileError(path_ + ": " + (key_.empty() ? "the document" : key_) + " " + why);
  }
  bool has(const std::string& name) const { return j_.is_object() && j_.contains(name); }
  Value operator[](const std::string& name) const {
    if (!j_.is_object())
      fail("is not an object");
    if (!j_.contains(name))
      throw FileError(path_ + ": " + key_ + (key_.empty() ? "" : ".") + name + " is missing");
    return Value(j_.at(name), path_, key_ + (key_.empty() ? "" : ".") + name);
  }
  Value at(std::size_t i) const {
    return Value(j_.at(i), path_, key_ + "[" + std::to_string(i) + "]");
  }
  std::size_t arraySize() const {
    if (!j_.is_array())
      fail("is not an array");
    return j_.size();
  }
  double number() const {
    if (!j_.is_number())
      fail("is not a number");
    const double v = j_.get<double>();
    if (!std::isfinite(v))
      fail("is not finite");
    return v;
  }
  int integer() const {
    if (!j_.is_number_integer())
      fail("is not an integer");
    const auto v = j_.get<long long>();
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      fail("is out of range");
    return static_cast<int>(v);
  }
  std::vector<double> numbers(std::size_t count) const {
    if (arraySize() != count)
      fail("holds " + std::to_string(j_.size()) + " numbers, not " + std::to_string(count));
    std::vector<double> v;
    for (std::size_t i = 0; i < count; ++i)
      v.push_back(at(i).number());
    return v;
  }
  Eigen::Vector3d vector3() const {
    const auto v = numbers(3);
    return {v[0], v[1], v[2]};
  }
  Eigen::Matrix3d matrix3() const {
    const auto v = numbers(9);
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        m(r, c) = v[static_cast<std::size_t>(3 * r + c)];
    return m;
  }
  /** An object's members whose names are integers (BOP's image and object ids). */
  std::vector<std::pair<int, Value>> byId() const {
    if (!j_.is_object())
      fail("is not an object");
    std::vector<std::pair<int, Value>> out;
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      std::size_t used = 0;
      int id = 0;
      try {
        id = std::stoi(it.key(), &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != it.key().size())
        throw FileError(path_ + ": key \"" + it.key() + "\" is not an id");
      out.emplace_back(id, Value(it.value(), path_, (key_.empty() ? "" : key_ + ".") + it.key()));
    }
    return out;
  }

 private:
  const json& j_;
  std::string path_, key_;
};

/** R row-major (9 numbers) and t (3) as an isometry; R must be a rotation. */
Eigen::Isometry3d rigid(const Value& R, const Value& t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = R.matrix3();
  pose.translation() = t.vector3();
  const Eigen::Matrix3d r = pose.linear();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-3 || r.determinant() < 0.0)
    R.fail("is not a rotation");
  return pose;
}

Eigen::Isometry3d transform4x4(const Value& v) {
  const auto m = v.numbers(16);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      t.linear()(r, c) = m[static_cast<std::size_t>(4 * r + c)];
    t.translation()[r] = m[static_cast<std::size_t>(4 * r + 3)];
  }
  return t;
}

/** The image of a PNG: its size, channels and bit depth, row 0 at the top. */
struct PngImage {
  int width = 0, height = 0, channels = 0;
  bool sixteen_bit = false;
  std::vector<std::uint16_t> values;  ///< channels per pixel, row-major from the top
};

/** What libpng decodes: rows of bytes, 16-bit samples in the host's order. */
struct PngDecode {
  std::vector<unsigned char> data;
  std::vector<png_bytep> rows;
  png_uint_32 width = 0, height = 0;
  int channels = 0, bit_depth = 0;
};

[[noreturn]] void pngFailed(png_structp png, png_const_charp) {
  png_longjmp(png, 1);
}
void pngWarned(png_structp, png_const_charp) {}

/** Decodes \a file into \a out; false for any libpng error (a truncated or corrupt file). The
 * classic API, as libpng documents it: its errors come back through setjmp into this frame,
 * which holds nothing that needs destroying beyond what it destroys itself. */
bool decodePng(std::FILE* file, PngDecode* out) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, pngFailed, pngWarned);
  if (!png)
    return false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_init_io(png, file);
  png_read_info(png, info);
  const int colour = png_get_color_type(png, info);
  if (colour == PNG_COLOR_TYPE_PALETTE)
    png_set_palette_to_rgb(png);
  if (colour == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(png, info) < 8)
    png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_bit_depth(png, info) == 16)
    png_set_swap(png);  // PNG stores 16-bit samples big-endian
  png_read_update_info(png, info);
  out->width = png_get_image_width(png, info);
  out->height = png_get_image_height(png, info);
  out->channels = png_get_channels(png, info);
  out->bit_depth = png_get_bit_depth(png, info);
  const png_size_t row_bytes = png_get_rowbytes(png, info);
  if (out->width == 0 || out->height == 0 || out->width > 65536 || out->height > 65536) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  out->data.resize(row_bytes * out->height);
  out->rows.resize(out->height);
  for (png_uint_32 v = 0; v < out->height; ++v)
    out->rows[v] = out->data.data() + v * row_bytes;
  png_read_image(png, out->rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

PngImage readPng(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file || !std::filesystem::is_regular_file(path))
    throw FileError(path + ": cannot be read");
  unsigned char signature[8] = {};
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
    throw FileError(path + ": not a PNG image");
  std::rewind(file.get());
  PngDecode decoded;
  if (!decodePng(file.get(), &decoded))
    throw FileError(path + ": cannot be decoded (truncated or corrupt)");
  PngImage png;
  png.width = static_cast<int>(decoded.width);
  png.height = static_cast<int>(decoded.height);
  png.channels = decoded.channels;
  png.sixteen_bit = decoded.bit_depth == 16;
  const std::size_t samples = static_cast<std::size_t>(png.width) * png.channels;
  png.values.resize(samples * static_cast<std::size_t>(png.height));
  for (int v = 0; v < png.height; ++v)
    for (std::size_t k = 0; k < samples; ++k) {
      const unsigned char* row = decoded.rows[static_cast<std::size_t>(v)];
      std::uint16_t value = row[k];
      if (png.sixteen_bit)
        std::memcpy(&value, row + 2 * k, sizeof(value));
      png.values[static_cast<std::size_t>(v) * samples + k] = value;
    }
  return png;
}

}  // namespace

std::map<int, BopModelInfo> readBopModelsInfo(const std::string& path) {
  const json j = readJson(path);
  std::map<int, BopModelInfo> out;
  for (const auto& [id, entry] : Value(j, path, "").byId()) {
    BopModelInfo info;
    info.diameter = entry["diameter"].number();
    if (!(info.diameter > 0.0))
      entry["diameter"].fail("must be > 0");
    if (entry.has("min_x")) {
      info.min = {entry["min_x"].number(), entry["min_y"].number(), entry["min_z"].number()};
      info.size = {entry["size_x"].number(), entry["size_y"].number(), entry["size_z"].number()};
    }
    if (entry.has("symmetries_discrete")) {
      const Value list = entry["symmetries_discrete"];
      for (std::size_t k = 0; k < list.arraySize(); ++k) {
        const Eigen::Isometry3d s = transform4x4(list.at(k));
        const Eigen::Matrix3d r = s.linear();
        if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-3)
          list.at(k).fail("is not a rigid transform");
        info.symmetries_discrete.push_back(s);
      }
    }
    if (entry.has("symmetries_continuous")) {
      const Value list = entry["symmetries_continuous"];
      for (std::size_t k = 0; k < list.arraySize(); ++k) {
        BopModelInfo::Continuous c;
        c.axis = list.at(k)["axis"].vector3();
        c.offset = list.at(k)["offset"].vector3();
        if (!(c.axis.norm() > 0.0))
          list.at(k)["axis"].fail("is zero");
        info.symmetries_continuous.push_back(c);
      }
    }
    out[id] = info;
  }
  return out;
}

std::vector<BopTarget> readBopTargets(const std::string& path) {
  const json j = readJson(path);
  const Value list(j, path, "");
  std::vector<BopTarget> out;
  for (std::size_t k = 0; k < list.arraySize(); ++k) {
    const Value e = list.at(k);
    BopTarget t;
    t.scene_id = e["scene_id"].integer();
    t.im_id = e["im_id"].integer();
    t.obj_id = e["obj_id"].integer();
    t.inst_count = e["inst_count"].integer();
    if (t.inst_count < 1)
      e["inst_count"].fail("must be >= 1");
    out.push_back(t);
  }
  return out;
}

BopCamera readBopDatasetCamera(const std::string& path) {
  const json j = readJson(path);
  const Value v(j, path, "");
  BopCamera camera;
  camera.K << v["fx"].number(), 0, v["cx"].number(), 0, v["fy"].number(), v["cy"].number(), 0, 0, 1;
  camera.width = v["width"].integer();
  camera.height = v["height"].integer();
  if (camera.width < 1 || camera.height < 1)
    v["width"].fail("and height must be >= 1");
  if (v.has("depth_scale"))
    camera.depth_scale = v["depth_scale"].number();
  if (!(camera.depth_scale > 0.0))
    v["depth_scale"].fail("must be > 0");
  return camera;
}

std::map<int, BopCamera> readBopSceneCamera(const std::string& path, int width, int height) {
  const json j = readJson(path);
  std::map<int, BopCamera> out;
  for (const auto& [id, entry] : Value(j, path, "").byId()) {
    BopCamera camera;
    camera.K = entry["cam_K"].matrix3();
    if (!(camera.K(0, 0) > 0.0 && camera.K(1, 1) > 0.0))
      entry["cam_K"].fail("has a focal length <= 0");
    camera.depth_scale = entry["depth_scale"].number();
    if (!(camera.depth_scale > 0.0))
      entry["depth_scale"].fail("must be > 0");
    if (entry.has("cam_R_w2c"))
      camera.world_to_camera = rigid(entry["cam_R_w2c"], entry["cam_t_w2c"]);
    camera.width = width;
    camera.height = height;
    out[id] = camera;
  }
  return out;
}

std::map<int, std::vector<BopPose>> readBopSceneGt(const std::string& path) {
  const json j = readJson(path);
  std::map<int, std::vector<BopPose>> out;
  for (const auto& [id, list] : Value(j, path, "").byId()) {
    std::vector<BopPose>& poses = out[id];
    for (std::size_t k = 0; k < list.arraySize(); ++k) {
      BopPose p;
      p.obj_id = list.at(k)["obj_id"].integer();
      p.model_to_camera = rigid(list.at(k)["cam_R_m2c"], list.at(k)["cam_t_m2c"]);
      poses.push_back(p);
    }
  }
  return out;
}

std::map<int, std::vector<double>> readBopSceneVisibility(const std::string& path) {
  const json j = readJson(path);
  std::map<int, std::vector<double>> out;
  for (const auto& [id, list] : Value(j, path, "").byId())
    for (std::size_t k = 0; k < list.arraySize(); ++k)
      out[id].push_back(list.at(k)["visib_fract"].number());
  return out;
}

pcl::PointCloud<pcl::PointXYZRGBA>::Ptr readBopDepthImage(const std::string& depth_png,
                                                          const BopCamera& camera,
                                                          const std::string& rgb_png) {
  if (!(camera.depth_scale > 0.0))
    throw FileError(depth_png + ": depth_scale " + std::to_string(camera.depth_scale) +
                    " must be > 0");
  const PngImage depth = readPng(depth_png);
  if (!depth.sixteen_bit || depth.channels != 1)
    throw FileError(depth_png + ": not a 16-bit single-channel depth image (" +
                    std::to_string(depth.channels) + " channels of " +
                    (depth.sixteen_bit ? "16" : "8") + " bits)");
  if (camera.width > 0 && (depth.width != camera.width || depth.height != camera.height))
    throw FileError(depth_png + ": " + std::to_string(depth.width) + " x " +
                    std::to_string(depth.height) + ", the camera's images are " +
                    std::to_string(camera.width) + " x " + std::to_string(camera.height));
  PngImage rgb;
  if (!rgb_png.empty()) {
    rgb = readPng(rgb_png);
    if (rgb.width != depth.width || rgb.height != depth.height || rgb.channels < 3 ||
        rgb.sixteen_bit)
      throw FileError(rgb_png + ": not an 8-bit colour image of the depth image's size");
  }
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZRGBA>>(
      static_cast<std::uint32_t>(depth.width), static_cast<std::uint32_t>(depth.height));
  cloud->is_dense = false;
  const double fx = camera.K(0, 0), fy = camera.K(1, 1), cx = camera.K(0, 2), cy = camera.K(1, 2);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < depth.height; ++v)
    for (int u = 0; u < depth.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * depth.width + u;
      pcl::PointXYZRGBA& p = (*cloud)(static_cast<std::size_t>(u), static_cast<std::size_t>(v));
      p.r = p.g = p.b = p.a = 255;
      if (!rgb_png.empty()) {
        p.r = static_cast<std::uint8_t>(rgb.values[i * rgb.channels]);
        p.g = static_cast<std::uint8_t>(rgb.values[i * rgb.channels + 1]);
        p.b = static_cast<std::uint8_t>(rgb.values[i * rgb.channels + 2]);
      }
      const double z = depth.values[i] * camera.depth_scale / 1000.0;
      if (depth.values[i] == 0) {
        p.x = p.y = p.z = nan;
        continue;
      }
      p.x = static_cast<float>((u - cx) * z / fx);
      p.y = static_cast<float>((v - cy) * z / fy);
      p.z = static_cast<float>(z);
    }
  return cloud;
}

}  // namespace io
}  // namespace icf
}  // namespace pcl
