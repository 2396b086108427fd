// Ground-truth poses of the shared real frames (../shared/data/ycbv*/gt.json), for tests.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

namespace pcl_icf_test {

/** The 4x4 pose (model -> camera) that follows the first mention of \a key in the gt.json at
 * \a gt_path: the first 16 numbers after the next '['. */
inline Eigen::Isometry3d ycbTruth(const std::string& gt_path, const std::string& key) {
  std::ifstream in(gt_path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t at = text.find(key);
  EXPECT_NE(at, std::string::npos) << key;
  at = text.find('[', at);
  Eigen::Matrix4d m;
  int filled = 0;
  const char* p = text.c_str() + at;
  while (filled < 16 && *p) {
    if ((*p >= '0' && *p <= '9') || *p == '-' || *p == '.') {
      char* end = nullptr;
      m(filled / 4, filled % 4) = std::strtod(p, &end);
      ++filled;
      p = end;
    } else
      ++p;
  }
  return Eigen::Isometry3d(m);
}

}  // namespace pcl_icf_test
