/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Prepared-model files (model_file.h). The layout is this project's own: PCL and VTK have no
// format for a closest-point field or a point pair table, and the file is a cache of our own
// arrays, read back on the same kind of machine (little-endian, the build's float layout). The
// checksum is zlib's CRC-32; the key is 64-bit FNV-1a (a few lines, stable across compilers and
// versions, which std::hash and boost::hash are not).
#include <pcl/icf/registration/model_file.h>

#include <pcl/common/io.h>

#include <zlib.h>

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <type_traits>

namespace pcl {
namespace icf {

namespace {

constexpr char kMagic[8] = {'P', 'C', 'L', 'I', 'C', 'F', 'M', '\0'};

/** 64-bit FNV-1a over everything fed to it. */
class KeyHash {
 public:
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
      h_ ^= p[i];
      h_ *= 0x100000001b3ULL;
    }
  }
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_arithmetic_v<T>);
    bytes(&v, sizeof(T));
  }
  template <typename... T>
  void values(const T&... v) {
    (value(v), ...);
  }
  void text(const std::string& s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  std::string hex() const {
    char out[17];
    std::snprintf(out, sizeof(out), "%016llx", static_cast<unsigned long long>(h_));
    return out;
  }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

/** Appends trivially copyable values and arrays to a byte buffer. */
class Writer {
 public:
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&v);
    buf_.insert(buf_.end(), p, p + sizeof(T));
  }
  template <typename... T>
  void values(const T&... v) {
    (value(v), ...);
  }
  template <typename T>
  void array(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value(static_cast<std::uint64_t>(v.size()));
    const auto* p = reinterpret_cast<const char*>(v.data());
    buf_.insert(buf_.end(), p, p + v.size() * sizeof(T));
  }
  std::string& bytes() { return buf_; }

 private:
  std::string buf_;
};

std::uint32_t crc(std::uint32_t running, const char* data, std::size_t n) {
  uLong c = running;
  // zlib's length is a uInt: feed large buffers in pieces.
  while (n > 0) {
    const auto piece = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
    c = crc32(c, reinterpret_cast<const Bytef*>(data), piece);
    data += piece;
    n -= piece;
  }
  return static_cast<std::uint32_t>(c);
}
std::uint32_t crc(const char* data, std::size_t n) {
  return crc(static_cast<std::uint32_t>(crc32(0L, Z_NULL, 0)), data, n);
}

/** Reads what Writer wrote straight from the file into its destination (one copy: a field is
 * tens of megabytes), every read checked against the file's end (a truncated file), and a
 * running CRC-32 of every byte read, compared by checksum() with the one stored there. */
class Reader {
 public:
  Reader(const std::string& path) : in_(path, std::ios::binary | std::ios::ate), path_(path) {
    if (!in_)
      throw ModelFileError(path + ": cannot be read");
    left_ = static_cast<std::uint64_t>(std::max<std::streamoff>(0, in_.tellg()));
    in_.seekg(0);
  }
  template <typename T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    take(reinterpret_cast<char*>(&v), sizeof(T), "ends early (truncated)");
    return v;
  }
  template <typename T>
  std::vector<T> array() {
    const auto n = value<std::uint64_t>();
    if (n > left_ / sizeof(T))
      fail("an array runs past the end (truncated)");
    std::vector<T> v(static_cast<std::size_t>(n));
    take(reinterpret_cast<char*>(v.data()), v.size() * sizeof(T), "ends early (truncated)");
    return v;
  }
  std::string text(std::size_t n) {
    std::string s(std::min<std::uint64_t>(n, left_), '\0');
    take(s.data(), n, "ends early (truncated)");
    return s;
  }
  /** Reads the CRC-32 stored next and compares it with that of every byte before it. */
  void checksum() {
    const std::uint32_t running = crc_;
    if (value<std::uint32_t>() != running)
      fail("checksum mismatch (corrupt or truncated)");
  }
  std::uint64_t left() const { return left_; }
  bool done() const { return left_ == 0; }
  [[noreturn]] void fail(const std::string& why) const { throw ModelFileError(path_ + ": " + why); }

 private:
  void take(char* to, std::size_t n, const char* short_why) {
    if (left_ < n)
      fail(short_why);
    if (!in_.read(to, static_cast<std::streamsize>(n)))
      fail("cannot be read");
    crc_ = crc(crc_, to, n);
    left_ -= n;
  }
  std::ifstream in_;
  std::string path_;
  std::uint64_t left_ = 0;
  std::uint32_t crc_ = static_cast<std::uint32_t>(crc32(0L, Z_NULL, 0));
};

/** Eigen's fixed vectors are not trivially copyable: written as their scalars. */
template <typename Scalar>
void put3(Writer& w, const Eigen::Matrix<Scalar, 3, 1>& v) {
  for (int a = 0; a < 3; ++a)
    w.value(v[a]);
}
template <typename Scalar>
Eigen::Matrix<Scalar, 3, 1> get3(Reader& r) {
  Eigen::Matrix<Scalar, 3, 1> v;
  for (int a = 0; a < 3; ++a)
    v[a] = r.value<Scalar>();
  return v;
}
void putPoints(Writer& w, const std::vector<Eigen::Vector3f>& points) {
  std::vector<float> flat;
  flat.reserve(3 * points.size());
  for (const auto& p : points)
    flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  w.array(flat);
}
std::vector<Eigen::Vector3f> getPoints(Reader& r) {
  const std::vector<float> flat = r.array<float>();
  if (flat.size() % 3 != 0)
    r.fail("a list of points is not a multiple of three numbers (corrupt)");
  std::vector<Eigen::Vector3f> points(flat.size() / 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = Eigen::Vector3f(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return points;
}

/** The mesh a file was prepared from, as PCL holds it: the vertex cloud's layout and bytes and
 * the faces' vertex indices. */
void putMesh(Writer& w, const pcl::PolygonMesh& mesh) {
  const pcl::PCLPointCloud2& c = mesh.cloud;
  w.values(c.width, c.height, c.point_step, c.row_step, c.is_bigendian, c.is_dense);
  w.value(static_cast<std::uint64_t>(c.fields.size()));
  for (const auto& f : c.fields) {
    w.value(static_cast<std::uint64_t>(f.name.size()));
    w.bytes().append(f.name);
    w.values(f.offset, f.datatype, f.count);
  }
  w.array(c.data);
  std::vector<std::uint64_t> sizes;
  std::vector<pcl::index_t> indices;
  sizes.reserve(mesh.polygons.size());
  for (const auto& p : mesh.polygons) {
    sizes.push_back(p.vertices.size());
    indices.insert(indices.end(), p.vertices.begin(), p.vertices.end());
  }
  w.array(sizes);
  w.array(indices);
}

pcl::PolygonMesh getMesh(Reader& r) {
  pcl::PolygonMesh mesh;
  pcl::PCLPointCloud2& c = mesh.cloud;
  c.width = r.value<decltype(c.width)>();
  c.height = r.value<decltype(c.height)>();
  c.point_step = r.value<decltype(c.point_step)>();
  c.row_step = r.value<decltype(c.row_step)>();
  c.is_bigendian = r.value<decltype(c.is_bigendian)>();
  c.is_dense = r.value<decltype(c.is_dense)>();
  const auto fields = r.value<std::uint64_t>();
  if (fields > 64)
    r.fail("the mesh's vertices have too many fields (corrupt)");
  for (std::uint64_t k = 0; k < fields; ++k) {
    pcl::PCLPointField f;
    const auto name = r.value<std::uint64_t>();
    if (name > 256)
      r.fail("a vertex field's name is too long (corrupt)");
    f.name = r.text(static_cast<std::size_t>(name));
    f.offset = r.value<decltype(f.offset)>();
    f.datatype = r.value<decltype(f.datatype)>();
    f.count = r.value<decltype(f.count)>();
    c.fields.push_back(f);
  }
  c.data = r.array<std::uint8_t>();
  // Sizes bounded first, so that their products fit 64 bits.
  if (c.point_step > (1u << 16) || c.height > (1u << 16) ||
      static_cast<std::uint64_t>(c.width) * c.height * c.point_step != c.data.size())
    r.fail("the mesh's vertex bytes do not match its size (corrupt)");
  for (const auto& f : c.fields)
    if (static_cast<std::uint64_t>(f.offset) +
            pcl::getFieldSize(f.datatype) * std::max(f.count, 1u) >
        c.point_step)
      r.fail("a vertex field lies outside its vertex (corrupt)");
  const std::vector<std::uint64_t> sizes = r.array<std::uint64_t>();
  const std::vector<pcl::index_t> indices = r.array<pcl::index_t>();
  std::size_t next = 0;
  mesh.polygons.resize(sizes.size());
  for (std::size_t p = 0; p < sizes.size(); ++p) {
    if (sizes[p] > indices.size() - next)
      r.fail("the mesh's faces run past their indices (corrupt)");
    mesh.polygons[p].vertices.assign(
        indices.begin() + static_cast<std::ptrdiff_t>(next),
        indices.begin() + static_cast<std::ptrdiff_t>(next + sizes[p]));
    next += sizes[p];
  }
  if (next != indices.size())
    r.fail("the mesh's faces leave indices over (corrupt)");
  return mesh;
}

/** A file's checked contents up to the model: the header, the key and the mesh, verified by
 * the magic, the version and the checksum after the mesh; \a reader left at the field. */
struct OpenedFile {
  std::unique_ptr<Reader> reader;
  std::string key;
  pcl::PolygonMesh mesh;
};

OpenedFile openModelFile(const std::string& path) {
  OpenedFile file;
  file.reader = std::make_unique<Reader>(path);
  Reader& r = *file.reader;
  if (r.left() < sizeof(kMagic) || r.text(sizeof(kMagic)) != std::string(kMagic, sizeof(kMagic)))
    r.fail("not a pcl_icf prepared model");
  const auto version = r.value<std::uint32_t>();
  if (version != kModelFileVersion)
    r.fail("format version " + std::to_string(version) + ", this build reads " +
           std::to_string(kModelFileVersion));
  const auto key_size = r.value<std::uint64_t>();
  if (key_size > 64)
    r.fail("its key is not a key (corrupt)");
  file.key = r.text(static_cast<std::size_t>(key_size));
  file.mesh = getMesh(r);
  r.checksum();
  return file;
}

}  // namespace

/** What the files hold of the classes' private state (their friend). */
struct ModelFileAccess {
  static void write(Writer& w, const ClosestPointField& f) {
    put3(w, f.origin_);
    put3(w, f.dims_);
    w.value(f.cell_);
    w.array(f.nodes_);
    w.array(f.distances_);
    w.array(f.medial_);
  }
  static std::unique_ptr<ClosestPointField> readField(Reader& r) {
    std::unique_ptr<ClosestPointField> f(new ClosestPointField());
    f->origin_ = get3<float>(r);
    f->dims_ = get3<int>(r);
    f->cell_ = r.value<float>();
    f->nodes_ = r.array<float>();
    f->distances_ = r.array<float>();
    f->medial_ = r.array<std::uint8_t>();
    // Each side at most 2^16 nodes: their product fits 64 bits whatever the file says.
    if (!(f->dims_.minCoeff() >= 2 && f->dims_.maxCoeff() <= (1 << 16)))
      r.fail("the closest-point field's sizes do not agree (corrupt)");
    const std::uint64_t nodes = static_cast<std::uint64_t>(f->dims_.x()) *
                                static_cast<std::uint64_t>(f->dims_.y()) *
                                static_cast<std::uint64_t>(f->dims_.z());
    if (!(f->cell_ > 0.f && std::isfinite(f->cell_) && f->nodes_.size() == 3 * nodes &&
          f->distances_.size() == nodes && f->medial_.size() == nodes))
      r.fail("the closest-point field's sizes do not agree (corrupt)");
    f->inv_cell_ = 1.f / f->cell_;
    return f;
  }
  static void write(Writer& w, const PointPairModel& m) {
    putPoints(w, m.points_);
    putPoints(w, m.normals_);
    w.values(m.diameter_, m.step_, m.coplanar_, m.angle_bins_, m.feature_bins_, m.distance_bins_);
    w.array(m.offsets_);
    w.array(m.entries_);
    w.array(m.weights_);
  }
  static std::unique_ptr<PointPairModel> readPairs(Reader& r, const PointPairModelParams& params) {
    auto m = std::make_unique<PointPairModel>();
    m->points_ = getPoints(r);
    m->normals_ = getPoints(r);
    m->diameter_ = r.value<float>();
    m->step_ = r.value<float>();
    m->coplanar_ = r.value<float>();
    m->angle_bins_ = r.value<int>();
    m->feature_bins_ = r.value<int>();
    m->distance_bins_ = r.value<int>();
    m->offsets_ = r.array<std::uint32_t>();
    m->entries_ = r.array<PointPairModel::Entry>();
    m->weights_ = r.array<float>();
    const bool empty = m->points_.empty();
    // The table's shape is the parameters' (PointPairModel::build): the voting indexes by it.
    if (!empty &&
        !(m->angle_bins_ == params.angle_bins && m->feature_bins_ == (params.angle_bins + 1) / 2 &&
          m->distance_bins_ >= 1 && m->distance_bins_ <= (1 << 20) && m->step_ > 0.f &&
          std::isfinite(m->step_) && m->diameter_ > 0.f && std::isfinite(m->diameter_)))
      r.fail("the point pair table's shape is not its parameters' (corrupt)");
    const std::uint64_t bins = empty ? 0
                                     : static_cast<std::uint64_t>(m->distance_bins_) *
                                           m->feature_bins_ * m->feature_bins_ * m->feature_bins_;
    const bool sized = m->normals_.size() == m->points_.size() &&
                       (empty || (m->offsets_.size() == bins + 1 && m->weights_.size() == bins &&
                                  m->offsets_.back() == m->entries_.size()));
    if (!sized)
      r.fail("the point pair table's sizes do not agree (corrupt)");
    for (std::size_t b = 1; b < m->offsets_.size(); ++b)
      if (m->offsets_[b] < m->offsets_[b - 1])
        r.fail("the point pair table's bins overlap (corrupt)");
    for (const auto& e : m->entries_)
      if (e.reference >= m->points_.size())
        r.fail("the point pair table names a sample it does not hold (corrupt)");
    return m;
  }
  static IcfModel::ConstPtr assemble(const pcl::PolygonMesh& mesh, const IcfModelParams& params,
                                     std::unique_ptr<ClosestPointField> field,
                                     std::unique_ptr<PointPairModel> pairs) {
    return IcfModel::assemble(mesh, params, std::move(field), std::move(pairs));
  }
  static const ClosestPointField& field(const IcfModel& m) { return *m.field_; }
  static const PointPairModel& pairs(const IcfModel& m) { return m.point_pairs_; }
};

std::string preparationKey(const pcl::PolygonMesh& mesh, const IcfModelParams& params) {
  // A field added to one of these structs must be added to the key: their sizes are checked.
  static_assert(sizeof(FaceMeshOptions) == 12, "FaceMeshOptions changed: update the key");
  static_assert(sizeof(DistanceFieldParams) == 32, "DistanceFieldParams changed: update the key");
  static_assert(sizeof(PointPairModelParams) == 40, "PointPairModelParams changed: update the key");
  KeyHash h;
  h.text("pcl_icf prepared model");
  h.value(kModelFileVersion);
  const pcl::PCLPointCloud2& c = mesh.cloud;
  h.value(c.width);
  h.value(c.height);
  h.value(c.point_step);
  h.value(c.is_bigendian);
  for (const auto& f : c.fields) {
    h.text(f.name);
    h.value(f.offset);
    h.value(f.datatype);
    h.value(f.count);
  }
  h.value(c.data.size());
  h.bytes(c.data.data(), c.data.size());
  h.value(mesh.polygons.size());
  for (const auto& p : mesh.polygons) {
    h.value(p.vertices.size());
    h.bytes(p.vertices.data(), p.vertices.size() * sizeof(p.vertices[0]));
  }
  const auto& m = params.mesh;
  const auto& f = params.field;
  const auto& pp = params.point_pairs;
  h.values(m.planarity_tolerance, m.area_tolerance, m.scale);
  h.values(f.margin, f.cell_size, f.resolution, f.max_nodes);
  h.values(params.surface_samples, params.seed);
  h.values(pp.sampling_step, pp.angle_bins, pp.normal_split_deg, pp.coplanar_deg, pp.max_bin_pairs,
           pp.dense_samples, pp.seed);
  return h.hex();
}

void writeModelFile(const IcfModel& model, const pcl::PolygonMesh& mesh, const std::string& key,
                    const std::string& path) {
  Writer w;
  w.bytes().append(kMagic, sizeof(kMagic));
  w.value(static_cast<std::uint32_t>(kModelFileVersion));
  w.value(static_cast<std::uint64_t>(key.size()));
  w.bytes().append(key);
  putMesh(w, mesh);
  w.value(crc(w.bytes().data(), w.bytes().size()));
  ModelFileAccess::write(w, ModelFileAccess::field(model));
  ModelFileAccess::write(w, ModelFileAccess::pairs(model));
  w.value(crc(w.bytes().data(), w.bytes().size()));

  // A temporary name of this process and a random suffix beside the target, then one rename.
  namespace fs = std::filesystem;
  std::random_device entropy;
  const fs::path target(path);
  const fs::path tmp =
      target.parent_path() / ("." + target.filename().string() + "." + std::to_string(::getpid()) +
                              "." + std::to_string(entropy()) + ".tmp");
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(w.bytes().data(), static_cast<std::streamsize>(w.bytes().size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      fs::remove(tmp, ignored);
      throw ModelFileError(path + ": cannot be written");
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw ModelFileError(path + ": cannot be written (" + ec.message() + ")");
  }
}

namespace {

/** readModelFile for a mesh whose preparationKey is \a want. */
IcfModel::ConstPtr readModelFileWithKey(const std::string& path, const pcl::PolygonMesh& mesh,
                                        const IcfModelParams& params, const std::string& want) {
  OpenedFile file = openModelFile(path);
  Reader& r = *file.reader;
  if (file.key != want)
    r.fail("prepared from another mesh or other parameters (key " + file.key + ", wanted " + want +
           ")");
  auto field = ModelFileAccess::readField(r);
  auto pairs = ModelFileAccess::readPairs(r, params.point_pairs);
  r.checksum();
  if (!r.done())
    r.fail("holds more than a model (corrupt)");
  return ModelFileAccess::assemble(mesh, params, std::move(field), std::move(pairs));
}

}  // namespace

IcfModel::ConstPtr readModelFile(const std::string& path, const pcl::PolygonMesh& mesh,
                                 const IcfModelParams& params) {
  return readModelFileWithKey(path, mesh, params, preparationKey(mesh, params));
}

bool isModelFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[sizeof(kMagic)] = {};
  return in.read(magic, sizeof(magic)) && std::memcmp(magic, kMagic, sizeof(kMagic)) == 0;
}

pcl::PolygonMesh readModelFileMesh(const std::string& path) {
  return openModelFile(path).mesh;
}

std::string defaultModelCacheFolder() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return (std::filesystem::path(xdg) / "pcl_icf").string();
  if (const char* home = std::getenv("HOME"); home && *home)
    return (std::filesystem::path(home) / ".cache" / "pcl_icf").string();
  return "";
}

CachedModel buildModelCached(const pcl::PolygonMesh& mesh, const IcfModelParams& params,
                             const std::string& folder) {
  CachedModel out;
  if (folder.empty()) {
    out.model = IcfModel::build(mesh, params);
    return out;
  }
  namespace fs = std::filesystem;
  const std::string key = preparationKey(mesh, params);
  out.path = (fs::path(folder) / (key + ".icfmodel")).string();
  std::error_code ec;
  if (fs::exists(out.path, ec)) {
    try {
      out.model = readModelFileWithKey(out.path, mesh, params, key);
      out.from_cache = true;
      return out;
    } catch (const ModelFileError& e) {
      out.warning = std::string(e.what()) + "; rebuilt";
    }
  }
  out.model = IcfModel::build(mesh, params);
  fs::create_directories(folder, ec);
  try {
    writeModelFile(*out.model, mesh, key, out.path);
  } catch (const ModelFileError& e) {
    out.warning +=
        (out.warning.empty() ? "" : "; ") + std::string(e.what()) + " (the model is not cached)";
  }
  return out;
}

}  // namespace icf
}  // namespace pcl
