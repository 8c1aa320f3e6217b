#include "compare/simd.h"

namespace nightcap::simd {

const char* path_name(Path path) {
  switch (path) {
    case Path::generic:
      return "generic";
    case Path::avx2:
      return "avx2";
    case Path::avx512:
      return "avx512";
  }
  return "?";
}

bool cpu_has(Path path) {
#if defined(__x86_64__) && defined(__GNUC__)
  // Needed where this runs before the constructors that would otherwise call it.
  __builtin_cpu_init();
  switch (path) {
    case Path::generic:
      return true;
    case Path::avx2:
      return __builtin_cpu_supports("avx2");
    case Path::avx512:
      return __builtin_cpu_supports("avx512f");
  }
  return false;
#else
  return path == Path::generic;
#endif
}

std::vector<Path> supported_paths() {
  std::vector<Path> paths;
  for (Path path : {Path::generic, Path::avx2, Path::avx512})
    if (cpu_has(path)) paths.push_back(path);
  return paths;
}

Path widest_path() {
  static const Path widest = supported_paths().back();
  return widest;
}

}  // namespace nightcap::simd
