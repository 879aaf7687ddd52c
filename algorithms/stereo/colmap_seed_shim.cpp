// Preloaded into COLMAP (LD_PRELOAD, algorithms/stereo/colmap_sfm.cpp) so that its runs repeat
// exactly. Measured on Debian's COLMAP 3.8 with one thread and a fixed --random_seed:
// the sequential matcher's raw matches differed between runs (one or two matches of a
// pair). FLANN's randomised kd-trees draw from std::random_device, and COLMAP's threads
// share the process-wide rand(); replacing either alone did not make the matches
// repeat, replacing both did. Here every thread draws from its own generator, seeded
// from GRAPEBENCH_COLMAP_SEED alone. With it, three runs gave byte-identical matches,
// geometries and models.
//
// A plain shared library, built without sanitizers (it is loaded into a program that
// is not instrumented); it includes no header of this project.
#include <cstdint>
#include <cstdlib>
#include <random>

namespace {

std::uint64_t seed_from_environment() {
  const char* s = std::getenv("GRAPEBENCH_COLMAP_SEED");
  return s ? std::strtoull(s, nullptr, 10) : 0;
}

// SplitMix64 (Steele, Lea and Flood 2014): one state word per thread.
struct ThreadStream {
  std::uint64_t state = seed_from_environment();
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
};
thread_local ThreadStream stream;

}  // namespace

extern "C" {
// RAND_MAX is 2^31 - 1 in glibc. A reseed restarts the thread's stream and ignores its
// argument: COLMAP's reseeds come from the clock.
int rand(void) { return static_cast<int>(stream.next() >> 33); }
void srand(unsigned) { stream.state = seed_from_environment(); }
long random(void) { return static_cast<long>(stream.next() >> 33); }
void srandom(unsigned) { stream.state = seed_from_environment(); }
}

// libstdc++'s std::random_device draws every value through this member.
unsigned int std::random_device::_M_getval() { return static_cast<unsigned>(stream.next() >> 32); }
