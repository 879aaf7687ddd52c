// Reading a user's own scan: PLY (ascii, binary little and big endian) and PCD (ascii,
// binary) point clouds, strictly. Every malformed header line, unknown type, short
// file, non-numeric or non-finite value is an InputError naming the file, the line
// (header) or the point (data) and what was allowed; a header that promises more data
// than the file holds fails before anything is allocated.
#pragma once

#include "algorithms/point_cloud.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace grapebench {

struct CloudFile {
  PointCloud points;           // N x 3, the file's units (metres for estimators)
  PointCloud normals;          // N x 3 when the file has nx ny nz / normal_x ..., else 0 x 3
  std::vector<Rgb8> colours;   // N when the file has red green blue / rgb, else empty
  std::size_t dropped_nan = 0;  // PCD points with a NaN coordinate (organised clouds' empty pixels), left out
  std::string format;          // "ply binary_little_endian", "pcd ascii", ...
};

// Reads `path` by its extension (.ply or .pcd, any case).
CloudFile read_cloud_file(const std::filesystem::path& path);

// The same from bytes in memory; `name` stands for the file in messages, `extension`
// is "ply" or "pcd".
CloudFile parse_cloud(const std::string& bytes, const std::string& name, const std::string& extension);

}  // namespace grapebench
