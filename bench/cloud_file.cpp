#include "bench/cloud_file.h"

#include "synth/config.h"
#include "synth/read_regular_file.h"

#include <algorithm>
#include <cstdio>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

namespace grapebench {

namespace {

constexpr std::size_t kMaxHeaderBytes = 1 << 20;
constexpr std::uint64_t kMaxPoints = std::uint64_t{1} << 31;
// Metres. Issue 39: a float property holding 1e39 (inf as a float) or a point at 1e308
// aborted PCL's kd-tree (cylinder_fit, every Poisson solver). Floats resolve 1 mm up
// to 8 km: 10 km bounds any vineyard scan in a local frame.
constexpr double kMaxCoordinate = 1e4;
// A whole file is read: 2 GiB holds 60 million points of x y z, normals and colour
// as floats (a file past it is refused before a byte of it is read).
constexpr std::size_t kMaxCloudFileBytes = std::size_t{2} << 30;

// The header's lines (without line ends) and where the data starts.
struct Header {
  std::vector<std::string> lines;
  std::size_t data_offset = 0;
};

// Lines up to and including the first whose first word is `last` ("end_header", "DATA").
Header read_header(const std::string& bytes, const std::string& name, const std::string& last) {
  Header h;
  std::size_t pos = 0;
  while (pos < bytes.size() && pos < kMaxHeaderBytes) {
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) end = bytes.size();
    std::string line = bytes.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    h.lines.push_back(line);
    pos = end + 1;
    std::istringstream words(line);
    std::string first;
    words >> first;
    if (first == last) {
      h.data_offset = std::min(pos, bytes.size());
      return h;
    }
  }
  throw InputError(name + ": no `" + last + "` line in the first " + std::to_string(h.lines.size()) +
                   " header lines (not a complete " + (last == "DATA" ? "PCD" : "PLY") + " header)");
}

std::vector<std::string> words_of(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> w;
  for (std::string x; s >> x;) w.push_back(x);
  return w;
}

[[noreturn]] void fail_line(const std::string& name, std::size_t line, const std::string& what) {
  throw InputError(name + ":" + std::to_string(line) + ": " + what);
}

std::uint64_t parse_count(const std::string& word, const std::string& name, std::size_t line, const std::string& key) {
  std::uint64_t v = 0;
  if (word.empty() || word.size() > 12 || !std::all_of(word.begin(), word.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
    fail_line(name, line, key + ": '" + word + "' is not a count (0.." + std::to_string(kMaxPoints) + ")");
  }
  v = std::stoull(word);
  if (v > kMaxPoints) fail_line(name, line, key + ": " + word + " is above the limit of " + std::to_string(kMaxPoints));
  return v;
}

// A number of an ascii data line: the whole token must convert.
double parse_number(const std::string& token, const std::string& where) {
  const char* s = token.c_str();
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (end == s || *end != '\0') throw InputError(where + ": '" + token + "' is not a number");
  return v;
}

// A scalar type of PLY or PCD: size in bytes and how to read it.
struct Scalar {
  int size = 0;
  char kind = 'F';  // I signed, U unsigned, F float
};

double read_scalar(const char* p, Scalar t, bool swap) {
  unsigned char b[8];
  std::memcpy(b, p, static_cast<std::size_t>(t.size));
  if (swap) std::reverse(b, b + t.size);
  switch (t.kind) {
    case 'F':
      if (t.size == 4) {
        float f;
        std::memcpy(&f, b, 4);
        return f;
      } else {
        double d;
        std::memcpy(&d, b, 8);
        return d;
      }
    case 'I': {
      std::int64_t v = 0;
      if (t.size == 1) v = static_cast<std::int8_t>(b[0]);
      if (t.size == 2) { std::int16_t x; std::memcpy(&x, b, 2); v = x; }
      if (t.size == 4) { std::int32_t x; std::memcpy(&x, b, 4); v = x; }
      if (t.size == 8) { std::int64_t x; std::memcpy(&x, b, 8); v = x; }
      return static_cast<double>(v);
    }
    default: {
      std::uint64_t v = 0;
      if (t.size == 1) v = b[0];
      if (t.size == 2) { std::uint16_t x; std::memcpy(&x, b, 2); v = x; }
      if (t.size == 4) { std::uint32_t x; std::memcpy(&x, b, 4); v = x; }
      if (t.size == 8) { std::uint64_t x; std::memcpy(&x, b, 8); v = x; }
      return static_cast<double>(v);
    }
  }
}

// The columns a cloud keeps, as indices into a record's values (-1: absent).
struct Columns {
  int xyz[3] = {-1, -1, -1}, normal[3] = {-1, -1, -1}, rgb[3] = {-1, -1, -1};
  int packed_rgb = -1;  // PCD's rgb / rgba: one 4-byte field holding 0x00RRGGBB
};

// Fills the cloud from per-point value rows; `packed` holds the raw 32-bit pattern of a
// packed colour field per point.
struct Builder {
  Columns cols;
  bool drop_nan = false;
  std::vector<double> xyz, nrm;
  std::vector<Rgb8> rgb;
  std::size_t dropped = 0;

  void add(const std::vector<double>& v, std::uint32_t packed, const std::string& name, std::uint64_t index) {
    const double x = v[static_cast<std::size_t>(cols.xyz[0])], y = v[static_cast<std::size_t>(cols.xyz[1])],
                 z = v[static_cast<std::size_t>(cols.xyz[2])];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      if (drop_nan && (std::isnan(x) || std::isnan(y) || std::isnan(z))) {
        ++dropped;
        return;
      }
      throw InputError(name + ": point " + std::to_string(index) + " has a non-finite coordinate");
    }
    if (std::max({std::abs(x), std::abs(y), std::abs(z)}) > kMaxCoordinate) {
      char why[200];
      std::snprintf(why, sizeof why, ": point %llu at (%g, %g, %g) m: coordinates must lie within +-%g m",
                    static_cast<unsigned long long>(index), x, y, z, kMaxCoordinate);
      throw InputError(name + why + " (move the cloud near the origin: beyond it single-precision kd-trees lose "
                                    "the millimetre, and 1e39 is no float at all)");
    }
    xyz.insert(xyz.end(), {x, y, z});
    if (cols.normal[0] >= 0) {
      for (int k = 0; k < 3; ++k) nrm.push_back(v[static_cast<std::size_t>(cols.normal[k])]);
    }
    if (cols.packed_rgb >= 0) {
      rgb.push_back({static_cast<std::uint8_t>(packed >> 16), static_cast<std::uint8_t>(packed >> 8),
                     static_cast<std::uint8_t>(packed)});
    } else if (cols.rgb[0] >= 0) {
      Rgb8 c;
      for (int k = 0; k < 3; ++k) {
        const double value = v[static_cast<std::size_t>(cols.rgb[k])];
        if (!(value >= 0 && value <= 255)) {
          throw InputError(name + ": point " + std::to_string(index) + ": colour " + std::to_string(value) +
                           " outside 0..255");
        }
        c[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(value);
      }
      rgb.push_back(c);
    }
  }

  CloudFile finish(std::string format) const {
    CloudFile f;
    f.format = std::move(format);
    const auto n = static_cast<Eigen::Index>(xyz.size() / 3);
    f.points = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(xyz.data(), n, 3);
    if (!nrm.empty()) f.normals = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(nrm.data(), n, 3);
    f.colours = rgb;
    f.dropped_nan = dropped;
    return f;
  }
};

// Issue 39: a file with more records than its header says, or a binary header over
// text, was accepted (its tail ignored). After the last record only whitespace
// (text) or nothing (binary) may follow.
void refuse_trailing(const std::string& bytes, std::size_t pos, bool ascii, const std::string& name,
                     const std::string& promised) {
  pos = std::min(pos, bytes.size());
  if (ascii) {
    const std::size_t next = bytes.find_first_not_of(" \t\r\n", pos);
    if (next == std::string::npos) return;
    throw InputError(name + ": line " + std::to_string(1 + std::count(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(next), '\n')) +
                     ": data after the " + promised + " the header promises");
  }
  if (pos != bytes.size())
    throw InputError(name + ": " + std::to_string(bytes.size() - pos) + " bytes after the " + promised +
                     " the header promises (byte " + std::to_string(pos) + " of " + std::to_string(bytes.size()) +
                     "; a text body under a binary header?)");
}

// ---- PLY ----

struct PlyProperty {
  std::string name;
  Scalar type;
  bool list = false;
  Scalar count_type;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> props;
};

std::optional<Scalar> ply_type(const std::string& t) {
  static const std::map<std::string, Scalar> types = {
      {"char", {1, 'I'}},   {"int8", {1, 'I'}},   {"uchar", {1, 'U'}},  {"uint8", {1, 'U'}},
      {"short", {2, 'I'}},  {"int16", {2, 'I'}},  {"ushort", {2, 'U'}}, {"uint16", {2, 'U'}},
      {"int", {4, 'I'}},    {"int32", {4, 'I'}},  {"uint", {4, 'U'}},   {"uint32", {4, 'U'}},
      {"float", {4, 'F'}},  {"float32", {4, 'F'}}, {"double", {8, 'F'}}, {"float64", {8, 'F'}}};
  const auto it = types.find(t);
  if (it == types.end()) return std::nullopt;
  return it->second;
}

Columns ply_columns(const PlyElement& v, const std::string& name) {
  Columns c;
  const auto find = [&](std::initializer_list<const char*> names) {
    for (std::size_t i = 0; i < v.props.size(); ++i) {
      for (const char* n : names) {
        if (v.props[i].name == n) {
          if (v.props[i].list) throw InputError(name + ": vertex property " + n + " is a list, not a number");
          return static_cast<int>(i);
        }
      }
    }
    return -1;
  };
  const char* axes[3][3] = {{"x", "nx", "red"}, {"y", "ny", "green"}, {"z", "nz", "blue"}};
  for (int k = 0; k < 3; ++k) {
    c.xyz[k] = find({axes[k][0]});
    c.normal[k] = find({axes[k][1], k == 0 ? "normal_x" : k == 1 ? "normal_y" : "normal_z"});
    c.rgb[k] = find({axes[k][2], k == 0 ? "r" : k == 1 ? "g" : "b", k == 0 ? "diffuse_red" : k == 1 ? "diffuse_green" : "diffuse_blue"});
  }
  if (c.xyz[0] < 0 || c.xyz[1] < 0 || c.xyz[2] < 0) {
    throw InputError(name + ": the vertex element lacks x, y or z (properties: " +
                     [&] {
                       std::string s;
                       for (const auto& p : v.props) s += (s.empty() ? "" : " ") + p.name;
                       return s;
                     }() + ")");
  }
  if ((c.normal[0] >= 0) != (c.normal[1] >= 0) || (c.normal[0] >= 0) != (c.normal[2] >= 0)) {
    throw InputError(name + ": the vertex element has some of nx, ny, nz but not all three");
  }
  if ((c.rgb[0] >= 0) != (c.rgb[1] >= 0) || (c.rgb[0] >= 0) != (c.rgb[2] >= 0)) {
    throw InputError(name + ": the vertex element has some of red, green, blue but not all three");
  }
  if (c.normal[0] < 0) c.normal[0] = c.normal[1] = c.normal[2] = -1;
  return c;
}

CloudFile parse_ply(const std::string& bytes, const std::string& name) {
  if (bytes.rfind("ply\n", 0) != 0 && bytes.rfind("ply\r\n", 0) != 0) {
    fail_line(name, 1, "not a PLY file (the first line must be `ply`)");
  }
  const Header h = read_header(bytes, name, "end_header");
  if (h.lines.empty() || h.lines[0] != "ply") fail_line(name, 1, "not a PLY file (the first line must be `ply`)");
  std::string format;
  std::vector<PlyElement> elements;
  for (std::size_t i = 1; i + 1 < h.lines.size(); ++i) {
    const auto w = words_of(h.lines[i]);
    const std::size_t line = i + 1;
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") ||
          w[2] != "1.0") {
        fail_line(name, line, "format: expected `format ascii|binary_little_endian|binary_big_endian 1.0`");
      }
      format = w[1];
    } else if (w[0] == "element") {
      if (w.size() != 3) fail_line(name, line, "element: expected `element <name> <count>`");
      elements.push_back({w[1], parse_count(w[2], name, line, "element " + w[1]), {}});
    } else if (w[0] == "property") {
      if (elements.empty()) fail_line(name, line, "property before any element");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        const auto ct = ply_type(w[2]), it = ply_type(w[3]);
        if (!ct || !it || ct->kind == 'F') fail_line(name, line, "property list: unknown or non-integer count type");
        p = {w[4], *it, true, *ct};
      } else if (w.size() == 3) {
        const auto t = ply_type(w[1]);
        if (!t) fail_line(name, line, "property " + w[2] + ": unknown type '" + w[1] + "' (char uchar short ushort int uint float double, or int8 ... float64)");
        p = {w[2], *t, false, {}};
      } else {
        fail_line(name, line, "property: expected `property <type> <name>` or `property list <count type> <type> <name>`");
      }
      for (const auto& q : elements.back().props)
        if (q.name == p.name) fail_line(name, line, "property " + p.name + " given twice in element " + elements.back().name);
      elements.back().props.push_back(p);
    } else {
      fail_line(name, line, "unknown header keyword '" + w[0] + "' (format, element, property, comment, end_header)");
    }
  }
  if (format.empty()) throw InputError(name + ": the header has no `format` line");
  const auto vertex_at = std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex_at == elements.end()) throw InputError(name + ": the header has no `element vertex`");
  Builder b;
  b.cols = ply_columns(*vertex_at, name);
  const bool ascii = format == "ascii", swap = format == "binary_big_endian";
  std::size_t pos = h.data_offset;
  std::vector<double> values;
  // Elements are read in order; all but the vertices are skipped (read to find the end).
  for (auto e = elements.begin(); e != elements.end(); ++e) {
    const bool keep = e == vertex_at;
    std::size_t fixed = 0;
    for (const auto& p : e->props) fixed += static_cast<std::size_t>(p.type.size);
    const std::size_t left = bytes.size() - pos;
    const std::size_t least = ascii ? 2 * std::max<std::size_t>(e->props.size(), 1) : std::max<std::size_t>(fixed, 1);
    if (e->count > left / least + (ascii ? 1 : 0)) {
      throw InputError(name + ": the header promises " + std::to_string(e->count) + " " + e->name + " records; the " +
                       std::to_string(left) + " bytes after it hold at most " + std::to_string(left / least));
    }
    if (keep) {
      b.xyz.reserve(3 * e->count);
      values.resize(e->props.size());
    }
    for (std::uint64_t r = 0; r < e->count; ++r) {
      const std::string where = name + ": " + e->name + " " + std::to_string(r);
      if (ascii) {
        std::size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) end = bytes.size();
        if (pos >= bytes.size()) throw InputError(where + ": the file ends (" + std::to_string(r) + " of " + std::to_string(e->count) + " read)");
        const auto tokens = words_of(bytes.substr(pos, end - pos));
        pos = end + 1;
        std::size_t t = 0;
        for (std::size_t k = 0; k < e->props.size(); ++k) {
          if (t >= tokens.size()) throw InputError(where + ": " + std::to_string(tokens.size()) + " values, too few for its properties");
          if (e->props[k].list) {
            const double n = parse_number(tokens[t++], where);
            if (!(n >= 0 && n <= 1e6) || n != std::floor(n)) throw InputError(where + ": list length '" + tokens[t - 1] + "' is not a count");
            t += static_cast<std::size_t>(n);
            if (t > tokens.size()) throw InputError(where + ": its list is longer than the line");
          } else {
            const double v = parse_number(tokens[t++], where);
            if (keep) values[k] = v;
          }
        }
        if (t != tokens.size()) throw InputError(where + ": " + std::to_string(tokens.size()) + " values where its properties take " + std::to_string(t));
      } else {
        for (std::size_t k = 0; k < e->props.size(); ++k) {
          const PlyProperty& p = e->props[k];
          std::size_t n = 1;
          if (p.list) {
            if (pos + static_cast<std::size_t>(p.count_type.size) > bytes.size()) throw InputError(where + ": the file ends inside it");
            const double len = read_scalar(bytes.data() + pos, p.count_type, swap);
            pos += static_cast<std::size_t>(p.count_type.size);
            if (!(len >= 0 && len <= 1e6)) throw InputError(where + ": list length " + std::to_string(len) + " outside 0..1000000");
            n = static_cast<std::size_t>(len);
          }
          if (pos + n * static_cast<std::size_t>(p.type.size) > bytes.size()) {
            throw InputError(where + ": the file ends inside it (" + std::to_string(r) + " of " + std::to_string(e->count) + " read)");
          }
          if (keep && !p.list) values[k] = read_scalar(bytes.data() + pos, p.type, swap);
          pos += n * static_cast<std::size_t>(p.type.size);
        }
      }
      if (keep) b.add(values, 0, name, r);
    }
  }
  refuse_trailing(bytes, pos, ascii, name, "records");
  return b.finish("ply " + format);
}

// ---- PCD ----

CloudFile parse_pcd(const std::string& bytes, const std::string& name) {
  const Header h = read_header(bytes, name, "DATA");
  std::map<std::string, std::pair<std::vector<std::string>, std::size_t>> keys;  // key -> (words, line)
  for (std::size_t i = 0; i < h.lines.size(); ++i) {
    auto w = words_of(h.lines[i]);
    if (w.empty() || w[0][0] == '#') continue;
    static const std::vector<std::string> known = {"VERSION", "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
    if (std::find(known.begin(), known.end(), w[0]) == known.end()) {
      fail_line(name, i + 1, "unknown header keyword '" + w[0] + "' (VERSION FIELDS SIZE TYPE COUNT WIDTH HEIGHT VIEWPOINT POINTS DATA)");
    }
    if (keys.count(w[0])) fail_line(name, i + 1, w[0] + " given twice");
    const std::string key = w[0];
    w.erase(w.begin());
    keys[key] = {w, i + 1};
  }
  for (const char* required : {"FIELDS", "SIZE", "TYPE", "WIDTH", "HEIGHT", "POINTS", "DATA"}) {
    if (!keys.count(required)) throw InputError(name + ": the PCD header has no " + std::string(required) + " line");
  }
  const auto& fields = keys["FIELDS"].first;
  const std::size_t nf = fields.size();
  for (std::size_t f = 0; f < nf; ++f)
    if (std::find(fields.begin(), fields.begin() + static_cast<std::ptrdiff_t>(f), fields[f]) != fields.begin() + static_cast<std::ptrdiff_t>(f))
      fail_line(name, keys["FIELDS"].second, "FIELDS: " + fields[f] + " given twice");
  const auto check_len = [&](const std::string& key) {
    if (keys[key].first.size() != nf) {
      fail_line(name, keys[key].second, key + ": " + std::to_string(keys[key].first.size()) + " entries for " + std::to_string(nf) + " FIELDS");
    }
  };
  check_len("SIZE");
  check_len("TYPE");
  std::vector<std::uint64_t> counts(nf, 1);
  if (keys.count("COUNT")) {
    check_len("COUNT");
    for (std::size_t f = 0; f < nf; ++f) {
      counts[f] = parse_count(keys["COUNT"].first[f], name, keys["COUNT"].second, "COUNT");
      if (counts[f] < 1 || counts[f] > 4096) fail_line(name, keys["COUNT"].second, "COUNT: " + keys["COUNT"].first[f] + " outside 1..4096");
    }
  }
  std::vector<Scalar> types(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::string& sz = keys["SIZE"].first[f];
    const std::string& ty = keys["TYPE"].first[f];
    const int size = sz == "1" ? 1 : sz == "2" ? 2 : sz == "4" ? 4 : sz == "8" ? 8 : 0;
    if (size == 0) fail_line(name, keys["SIZE"].second, "SIZE of " + fields[f] + ": '" + sz + "' (1, 2, 4 or 8)");
    if (ty != "I" && ty != "U" && ty != "F") fail_line(name, keys["TYPE"].second, "TYPE of " + fields[f] + ": '" + ty + "' (I, U or F)");
    if (ty == "F" && size < 4) fail_line(name, keys["TYPE"].second, "TYPE F of " + fields[f] + " needs SIZE 4 or 8");
    types[f] = {size, ty[0]};
  }
  const std::uint64_t width = parse_count(keys["WIDTH"].first.empty() ? "" : keys["WIDTH"].first[0], name, keys["WIDTH"].second, "WIDTH");
  const std::uint64_t height = parse_count(keys["HEIGHT"].first.empty() ? "" : keys["HEIGHT"].first[0], name, keys["HEIGHT"].second, "HEIGHT");
  const std::uint64_t points = parse_count(keys["POINTS"].first.empty() ? "" : keys["POINTS"].first[0], name, keys["POINTS"].second, "POINTS");
  if (width * height != points) {
    fail_line(name, keys["POINTS"].second, "POINTS " + std::to_string(points) + " is not WIDTH x HEIGHT = " + std::to_string(width * height));
  }
  const auto& data = keys["DATA"].first;
  if (data.size() != 1 || (data[0] != "ascii" && data[0] != "binary")) {
    fail_line(name, keys["DATA"].second, "DATA: '" + (data.empty() ? std::string() : data[0]) +
              "' (ascii or binary; convert binary_compressed with `pcl_convert_pcd_ascii_binary <in> <out> 1`)");
  }
  // Value slots: one per field element; the cloud's columns point at a field's first.
  std::vector<std::size_t> first_slot(nf);
  std::size_t slots = 0, record = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    first_slot[f] = slots;
    slots += counts[f];
    record += counts[f] * static_cast<std::size_t>(types[f].size);
  }
  Builder b;
  b.drop_nan = true;  // organised clouds mark empty pixels with NaN
  const auto field = [&](const char* n) {
    const auto it = std::find(fields.begin(), fields.end(), n);
    return it == fields.end() ? -1 : static_cast<int>(first_slot[static_cast<std::size_t>(it - fields.begin())]);
  };
  const char* axes[3] = {"x", "y", "z"};
  const char* normals[3] = {"normal_x", "normal_y", "normal_z"};
  for (int k = 0; k < 3; ++k) {
    b.cols.xyz[k] = field(axes[k]);
    b.cols.normal[k] = field(normals[k]);
  }
  if (b.cols.xyz[0] < 0 || b.cols.xyz[1] < 0 || b.cols.xyz[2] < 0) {
    fail_line(name, keys["FIELDS"].second, "FIELDS lack x, y or z");
  }
  if ((b.cols.normal[0] >= 0) != (b.cols.normal[1] >= 0) || (b.cols.normal[0] >= 0) != (b.cols.normal[2] >= 0)) {
    fail_line(name, keys["FIELDS"].second, "FIELDS have some of normal_x, normal_y, normal_z but not all three");
  }
  if (b.cols.normal[0] < 0) b.cols.normal[0] = b.cols.normal[1] = b.cols.normal[2] = -1;
  int packed_field = -1;
  for (const char* n : {"rgb", "rgba"}) {
    const auto it = std::find(fields.begin(), fields.end(), n);
    if (it != fields.end()) packed_field = static_cast<int>(it - fields.begin());
  }
  if (packed_field >= 0) {
    if (types[static_cast<std::size_t>(packed_field)].size != 4) fail_line(name, keys["SIZE"].second, "the rgb field must have SIZE 4");
    b.cols.packed_rgb = static_cast<int>(first_slot[static_cast<std::size_t>(packed_field)]);
  }
  const bool ascii = data[0] == "ascii";
  std::size_t pos = h.data_offset;
  const std::size_t left = bytes.size() - pos;
  const std::size_t least = ascii ? 2 * slots : record;
  if (points > left / least + (ascii ? 1 : 0)) {
    throw InputError(name + ": the header promises " + std::to_string(points) + " points; the " + std::to_string(left) +
                     " bytes after it hold at most " + std::to_string(left / least));
  }
  b.xyz.reserve(3 * points);
  std::vector<double> values(slots);
  for (std::uint64_t r = 0; r < points; ++r) {
    std::uint32_t packed = 0;
    const std::string where = name + ": point " + std::to_string(r);
    if (ascii) {
      if (pos >= bytes.size()) throw InputError(where + ": the file ends (" + std::to_string(r) + " of " + std::to_string(points) + " read)");
      std::size_t end = bytes.find('\n', pos);
      if (end == std::string::npos) end = bytes.size();
      const auto tokens = words_of(bytes.substr(pos, end - pos));
      pos = end + 1;
      if (tokens.size() != slots) throw InputError(where + ": " + std::to_string(tokens.size()) + " values where FIELDS and COUNT take " + std::to_string(slots));
      for (std::size_t k = 0; k < slots; ++k) {
        const std::string& t = tokens[k];
        values[k] = (t == "nan" || t == "NaN" || t == "-nan") ? std::numeric_limits<double>::quiet_NaN() : parse_number(t, where);
      }
      if (b.cols.packed_rgb >= 0) {
        const double v = values[static_cast<std::size_t>(b.cols.packed_rgb)];
        if (types[static_cast<std::size_t>(packed_field)].kind == 'F') {
          const float f = static_cast<float>(v);
          std::memcpy(&packed, &f, 4);
        } else {
          packed = static_cast<std::uint32_t>(v);
        }
      }
    } else {
      if (pos + record > bytes.size()) throw InputError(where + ": the file ends inside it (" + std::to_string(r) + " of " + std::to_string(points) + " read)");
      std::size_t slot = 0;
      for (std::size_t f = 0; f < nf; ++f) {
        for (std::uint64_t c = 0; c < counts[f]; ++c, ++slot) {
          if (static_cast<int>(f) == packed_field) std::memcpy(&packed, bytes.data() + pos, 4);
          values[slot] = read_scalar(bytes.data() + pos, types[f], false);
          pos += static_cast<std::size_t>(types[f].size);
        }
      }
    }
    b.add(values, packed, name, r);
  }
  refuse_trailing(bytes, pos, ascii, name, std::to_string(points) + " points");
  return b.finish("pcd " + data[0]);
}

}  // namespace

CloudFile parse_cloud(const std::string& bytes, const std::string& name, const std::string& extension) {
  if (extension == "ply") return parse_ply(bytes, name);
  if (extension == "pcd") return parse_pcd(bytes, name);
  throw InputError(name + ": unknown point-cloud format '" + extension + "' (ply or pcd)");
}

CloudFile read_cloud_file(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != "ply" && ext != "pcd") throw InputError(path.string() + ": not a .ply or .pcd file");
  return parse_cloud(read_regular_file(path, kMaxCloudFileBytes), path.string(), ext);
}

}  // namespace grapebench
