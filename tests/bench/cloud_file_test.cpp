// bench/cloud_file: PLY and PCD in every encoding read to the same points; every
// malformed file is an InputError naming the file and the line or point.
#include "bench/cloud_file.h"

#include "synth/config.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

namespace grapebench {
namespace {

const double kPts[3][3] = {{0.1, -0.2, 0.3}, {1.5, 2.25, -3.125}, {0.0, 0.5, 1.0}};

template <class T>
void put(std::string& s, T v, bool big = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

// A binary PLY with a face element before the vertices (skipped) and one after (unread).
std::string binary_ply(bool big) {
  std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\ncomment test\nelement face 1\nproperty list uchar int vertex_indices\n"
                  "element vertex 3\nproperty double x\nproperty float y\nproperty float z\n"
                  "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty short extra\n"
                  "element edge 1\nproperty int a\nend_header\n";
  put<std::uint8_t>(s, 3);
  for (int i = 0; i < 3; ++i) put<std::int32_t>(s, i, big);
  for (const auto& p : kPts) {
    put<double>(s, p[0], big);
    put<float>(s, static_cast<float>(p[1]), big);
    put<float>(s, static_cast<float>(p[2]), big);
    for (std::uint8_t c : {std::uint8_t{10}, std::uint8_t{20}, std::uint8_t{30}}) put<std::uint8_t>(s, c);
    put<std::int16_t>(s, -7, big);
  }
  put<std::int32_t>(s, 5, big);
  return s;
}

void expect_points(const CloudFile& f) {
  ASSERT_EQ(f.points.rows(), 3);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(f.points(i, k), kPts[i][k], 1e-7) << i << "," << k;
  }
}

TEST(CloudFile, BinaryPlyBothEndiansAndAsciiReadTheSamePoints) {
  for (bool big : {false, true}) {
    const CloudFile f = parse_cloud(binary_ply(big), "t.ply", "ply");
    expect_points(f);
    ASSERT_EQ(f.colours.size(), 3u);
    EXPECT_EQ(f.colours[2][1], 20);
    EXPECT_EQ(f.normals.rows(), 0);
  }
  const std::string ascii =
      "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
      "property float nx\r\nproperty float ny\r\nproperty float nz\r\nelement face 1\r\n"
      "property list uchar int vertex_indices\r\nend_header\r\n"
      "0.1 -0.2 0.3 0 0 1\r\n1.5 2.25 -3.125 0 0 1\r\n0 0.5 1 0 1 0\r\n3 0 1 2\r\n";
  const CloudFile f = parse_cloud(ascii, "a.ply", "ply");
  expect_points(f);
  ASSERT_EQ(f.normals.rows(), 3);
  EXPECT_EQ(f.normals(2, 1), 1.0);
  EXPECT_EQ(f.format, "ply ascii");
}

TEST(CloudFile, PcdAsciiAndBinaryDropNanPixelsAndUnpackRgb) {
  const float packed_f = [] {
    const std::uint32_t rgb = (200u << 16) | (100u << 8) | 50u;
    float f;
    std::memcpy(&f, &rgb, 4);
    return f;
  }();
  std::string bin =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb label\nSIZE 4 4 4 4 4\nTYPE F F F F U\nCOUNT 1 1 1 1 1\n"
      "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA binary\n";
  for (int i = 0; i < 4; ++i) {
    const bool nan = i == 1;
    const auto& p = kPts[i < 1 ? 0 : i - 1];
    for (int k = 0; k < 3; ++k) put<float>(bin, nan ? NAN : static_cast<float>(p[k]));
    put<float>(bin, packed_f);
    put<std::uint32_t>(bin, 2);
  }
  const CloudFile b = parse_cloud(bin, "b.pcd", "pcd");
  expect_points(b);
  EXPECT_EQ(b.dropped_nan, 1u);
  ASSERT_EQ(b.colours.size(), 3u);
  EXPECT_EQ(b.colours[0][0], 200);
  EXPECT_EQ(b.colours[0][2], 50);
  const std::string ascii =
      "VERSION .7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 8 8 8 4 4 4\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\n"
      "WIDTH 4\nHEIGHT 1\nPOINTS 4\nDATA ascii\n0.1 -0.2 0.3 0 0 1\nnan nan nan nan nan nan\n"
      "1.5 2.25 -3.125 1 0 0\n0 0.5 1 0 1 0\n";
  const CloudFile a = parse_cloud(ascii, "a.pcd", "pcd");
  expect_points(a);
  EXPECT_EQ(a.dropped_nan, 1u);
  EXPECT_EQ(a.normals(1, 0), 1.0);
}

// Each malformed file: an InputError whose message holds every fragment.
void expect_error(const std::string& bytes, const std::string& ext, std::initializer_list<const char*> fragments) {
  try {
    parse_cloud(bytes, "bad." + ext, ext);
    ADD_FAILURE() << "accepted:\n" << bytes.substr(0, 200);
  } catch (const InputError& e) {
    const std::string m = e.what();
    for (const char* f : fragments) EXPECT_NE(m.find(f), std::string::npos) << "'" << f << "' not in: " << m;
  }
}

TEST(CloudFile, MalformedFilesNameFileLineAndWhatWasAllowed) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n";
  expect_error("plx\n", "ply", {"bad.ply:1", "not a PLY"});
  expect_error("ply\nformat ascii 2.0\nend_header\n", "ply", {"bad.ply:2", "format"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 2\nproperty quad x\nend_header\n", "ply", {"bad.ply:4", "unknown type 'quad'"});
  expect_error("ply\nformat ascii 1.0\nelement vertex -2\nend_header\n", "ply", {"bad.ply:3", "not a count"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nend_header\n1 2\n3 4\n", "ply", {"lacks x, y or z"});
  expect_error(head + "end_header\n1 2 3\n", "ply", {"the file ends"});
  expect_error(head + "end_header\n1 2 3\n1 two 3\n", "ply", {"vertex 1", "'two' is not a number"});
  expect_error(head + "end_header\n1 2 3\n1 2 3 4\n", "ply", {"vertex 1", "4 values"});
  expect_error(head + "end_header\n1 2 3\n1 2 inf\n", "ply", {"point 1", "non-finite"});
  expect_error(head + "wat\nend_header\n", "ply", {"bad.ply:7", "unknown header keyword 'wat'"});
  expect_error(head, "ply", {"no `end_header`"});
  // A header promising a billion binary vertices fails before allocating them.
  expect_error("ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n" + std::string(24, '\0'), "ply", {"promises 1000000000", "at most 2"});
  std::string cut = binary_ply(false);
  cut.resize(cut.size() - 10);
  expect_error(cut, "ply", {"promises 3 vertex records"});

  const std::string pcd = "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  expect_error(pcd + "DATA binary_compressed\n", "pcd", {"bad.pcd:8", "binary_compressed"});
  expect_error("VERSION .7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n", "pcd",
               {"bad.pcd:3", "SIZE: 2 entries for 3 FIELDS"});
  expect_error("VERSION .7\nFIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n", "pcd",
               {"bad.pcd:3", "(1, 2, 4 or 8)"});
  expect_error("VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 2\nDATA ascii\n", "pcd",
               {"bad.pcd:7", "WIDTH x HEIGHT = 4"});
  expect_error("VERSION .7\nFIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "pcd",
               {"bad.pcd:2", "lack x, y or z"});
  expect_error(pcd + "DATA ascii\n1 2 3\n", "pcd", {"point 1", "the file ends"});
  expect_error(pcd + "DATA ascii\n1 2 3\n1 2\n", "pcd", {"point 1", "2 values"});
  expect_error(pcd + "DATA binary\n" + std::string(20, '\0'), "pcd", {"promises 2", "at most 1"});
  expect_error(pcd + "POINTS 2\nDATA ascii\n", "pcd", {"bad.pcd:8", "POINTS given twice"});
  expect_error("x", "obj", {"unknown point-cloud format 'obj'"});

  // Issue 39's reproducers: each was accepted (the tail ignored, the property read
  // twice) or reached PCL, whose float kd-tree aborted the process on 1e39.
  expect_error(head + "end_header\n1 2 3\n1 2 3\n4 5 6\n", "ply", {"bad.ply: line 10: data after the records"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\nproperty float z\n"
               "end_header\n1 2 3\n", "ply", {"bad.ply:5", "property x given twice"});
  expect_error(head + "end_header\n1 2 3\n1e39 0 0\n", "ply", {"point 1 at (1e+39, 0, 0) m", "within +-10000 m"});
  expect_error(head + "end_header\n1 2 3\n0 1e308 0\n", "ply", {"point 1", "within +-10000 m"});
  expect_error("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n1.25 2.5 3.5\n", "ply", {"1 bytes after the records", "a text body under a binary header"});
  expect_error(pcd + "DATA ascii\n1 2 3\n4 5 6\n7 8 9\n", "pcd", {"line 11: data after the 2 points"});
  expect_error("VERSION .7\nFIELDS x y x\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "pcd",
               {"bad.pcd:2", "FIELDS: x given twice"});
}

}  // namespace
}  // namespace grapebench
