#include "bench/build_info.h"
#include "synth/fnv1a.h"

#include "grapebench_git_describe.h"  // generated at build time (cmake/git_describe.cmake)

#include <CGAL/version.h>
#include <CLI/Version.hpp>
#include <Eigen/Core>
#include <GL/osmesa.h>
#include <embree3/rtcore_config.h>
#include <libsvm/svm.h>
#include <opencv2/core/version.hpp>
#include <pcl/pcl_config.h>
#include <tbb/info.h>
#include <tbb/version.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <mutex>
#include <vector>

#ifndef GRAPEBENCH_VERSION
#define GRAPEBENCH_VERSION "unknown"
#endif
#ifndef GRAPEBENCH_BUILD_TYPE
#define GRAPEBENCH_BUILD_TYPE "unknown"
#endif

namespace grapebench {

namespace {

#define GB_STR2(x) #x
#define GB_STR(x) GB_STR2(x)

std::string hash_file(const char* path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "unknown";
  std::uint64_t h = kFnv1aOffset;
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    h = fnv1a(std::string_view(buf.data(), static_cast<std::size_t>(in.gcount())), h);
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown";
}

}  // namespace

std::string version_string() { return std::string(GRAPEBENCH_VERSION) + " (" + GRAPEBENCH_GIT_DESCRIBE + ")"; }

const std::string& build_identity() {
  static std::once_flag once;
  static std::string id;
  std::call_once(once, [] { id = hash_file("/proc/self/exe"); });
  return id;
}

nlohmann::ordered_json build_info_json() {
  nlohmann::ordered_json j;
  j["version"] = GRAPEBENCH_VERSION;
  j["git_describe"] = GRAPEBENCH_GIT_DESCRIBE;
  j["build_identity"] = build_identity();
  j["build_type"] = GRAPEBENCH_BUILD_TYPE;
#if defined(__clang__)
  j["compiler"] = "clang " __clang_version__;
#elif defined(__GNUC__)
  j["compiler"] = "gcc " __VERSION__;
#else
  j["compiler"] = "unknown";
#endif
#if defined(__SANITIZE_ADDRESS__)
  j["sanitizers"] = "address,undefined";
#else
  j["sanitizers"] = "none";
#endif
  j["libraries"] = {
      {"embree", RTC_VERSION_STRING},
      {"pcl", PCL_VERSION_PRETTY},
      {"cgal", CGAL_VERSION_STR},
      {"opencv", CV_VERSION},
      {"eigen", GB_STR(EIGEN_WORLD_VERSION) "." GB_STR(EIGEN_MAJOR_VERSION) "." GB_STR(EIGEN_MINOR_VERSION)},
      {"tbb", TBB_VERSION_STRING},
      {"libsvm", GB_STR(LIBSVM_VERSION)},
      {"osmesa", GB_STR(OSMESA_MAJOR_VERSION) "." GB_STR(OSMESA_MINOR_VERSION) "." GB_STR(OSMESA_PATCH_VERSION)},
      {"nlohmann_json", GB_STR(NLOHMANN_JSON_VERSION_MAJOR) "." GB_STR(NLOHMANN_JSON_VERSION_MINOR) "." GB_STR(
                            NLOHMANN_JSON_VERSION_PATCH)},
      {"cli11", CLI11_VERSION},
#ifdef GRAPEBENCH_YAML_CPP_VERSION
      {"yaml_cpp", GRAPEBENCH_YAML_CPP_VERSION},
#endif
  };
  return j;
}

nlohmann::ordered_json machine_json() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return {{"host", host}, {"cpu", cpu_model()}, {"cores", tbb::info::default_concurrency()}};
}

}  // namespace grapebench
