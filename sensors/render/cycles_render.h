// The physically based reference: the same scene (berries as spheres, stems and canes
// as capped cylinders with their wood texture baked into an atlas (wood_atlas.h), the
// leaves with their texture and veins baked into an atlas,
// the row copies, ground, sun and sky, the camera with its thin lens) exported to
// Blender and rendered by Cycles, headless, through sensors/render/cycles_scene.py.
// Path tracing with every bounce; the materials are the appearance model's
// (sensors/render/appearance.h). Blender runs under a time limit and is stopped with
// everything it started when it ends or overruns (synth/confined_program.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "sensors/camera.h"
#include "sensors/ray_scene.h"
#include "sensors/render/appearance.h"
#include "sensors/render/develop_image.h"
#include "sensors/render/illumination.h"
#include "synth/confined_program.h"
#include "synth/param_table.h"

namespace grapebench {

struct CyclesParams {
  int samples = 64;           // path samples per pixel, [1, 4096]
  int bounces = 12;           // cap on every kind of light-path bounce, [1, 128]
  enum class Diffuse { Principled, Lambert };
  Diffuse diffuse = Diffuse::Principled;  // berries' and leaves' diffuse lobe; Lambert: the fast renderer's, an ablation
  int threads = 2;            // Cycles' render threads, [1, 256]
  double time_limit = 600;    // s per image, Blender's start included, [1, 86400]
  int leaf_texels = 256;      // texels per leaf side in the leaf atlas, [16, 2048]
  double wood_texel = 0.0005; // m, texel of the baked wood texture on the scene's stems and canes (row copies: twice), [1e-4, 0.01]
  ProgramLimits::Sandbox sandbox = ProgramLimits::Sandbox::Bwrap;  // as every program the harness starts
};
const ParamTable<CyclesParams>& cycles_param_table();

// How Blender is confined (synth/confined_program.h): `blender` is its path; a Blender
// outside /usr is shown its own folder. Its script and scene are the files it is given.
ProgramLimits cycles_program_limits(const CyclesParams& cycles, const std::string& blender);

struct CyclesRenderResult {
  std::vector<float> linear;      // H x W x 3, radiance times pi (as ray_render's)
  std::vector<std::uint8_t> part; // H x W, the Part of the object seen (Cycles' object-index pass); None elsewhere
  double seconds = 0;             // Blender's wall time, start-up included (0 from the cache)
  bool cached = false;            // read from the render cache (set_cycles_cache), Blender not run
};

// The render cache: a folder of Blender's answers keyed by what the harness gives
// Blender (the exported scene with the camera, light, samples, bounces, threads and
// seed, its atlases, the script) and Blender's binary by path, size and time (FNV-1a
// 64 over the bytes); not by Blender's libraries, data files or environment: clear
// the folder after changing those. A hit reads the bytes Blender wrote for the same
// input, so the image is the one a new render gives (Cycles is seeded), and skips
// `time_limit`. Empty (the default): no cache. `grapebench run` sets it to the run
// folder's cycles_cache/ (or its --cycles-cache, which `scan` and `dataset` take too), so a run that stopped, or a scene given another estimator,
// renders no image twice (an image takes 30-130 s); two cases of one run needing the
// same image at once render it once. An entry of the wrong size or holding a value
// that is not a radiance is rendered again and replaced; entries are written whole
// (renamed into place); an entry that cannot be written is warned about on stderr.
void set_cycles_cache(const std::filesystem::path& folder);
std::filesystem::path cycles_cache();

// The render cache for a scope (a run, a scan, a dataset); empty: the cache left as it
// is. Scopes share the process's one folder: while one lives, another naming a
// different folder (two runs in threads of one Python process) throws InputError, one
// naming the same folder joins it, and when the last ends the folder before the first
// is back. One folder can serve several scenes and commands: the key holds everything
// Blender is given, so a scene that differs in nothing Blender sees (another estimator,
// the same condition in another file) reads the same images.
class CyclesCacheScope {
 public:
  explicit CyclesCacheScope(const std::filesystem::path& folder);
  ~CyclesCacheScope();
  CyclesCacheScope(const CyclesCacheScope&) = delete;
  CyclesCacheScope& operator=(const CyclesCacheScope&) = delete;

 private:
  bool joined_ = false;
};

// Blender's path: $GRAPEBENCH_BLENDER, else `blender` from PATH. Throws InputError
// naming the Debian package when it is not there (a run asks before its first case, so
// a missing Blender is the run's exit 2, not a failed row per case).
std::string find_blender();

// Blender is find_blender()'s. `work` is a folder for the
// exported scene and Blender's outputs (created; left in place). Throws InputError when
// Blender is missing (naming the Debian package) and std::runtime_error when it fails
// or overruns, with its reason and the tail of its output.
CyclesRenderResult cycles_render(const RayScene& scene, const Camera& cam, const Illumination& light,
                                 const AppearanceParams& look, const PhotoCameraParams& camera, double focal_length,
                                 const CyclesParams& cycles, std::uint64_t seed, const std::filesystem::path& work);

}  // namespace grapebench
