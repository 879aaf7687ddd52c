// What built this binary: version, source revision, compiler, library versions, and
// an identity of the code itself (a hash of the running executable), so results
// computed by one build are never silently taken for another's.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace grapebench {

// "0.1.0 (v0.1.0-12-gabc1234-dirty)": the project version and `git describe --dirty`
// of the tree it was built from.
std::string version_string();

// 16 hex digits: FNV-1a 64 of the executable file (/proc/self/exe). Any change of the
// code, compiler, flags or statically linked library changes it; computed once.
const std::string& build_identity();

// Version, revision, build identity, compiler, build type, and the versions of every
// library compiled in (from their headers), as the manifest records them.
nlohmann::ordered_json build_info_json();

// This machine: CPU model (from /proc/cpuinfo), logical cores, host name.
nlohmann::ordered_json machine_json();

}  // namespace grapebench
