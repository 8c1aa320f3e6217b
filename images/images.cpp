#include "images/images.h"

#include <dlfcn.h>

#include <cstdlib>
#include <new>

#include "images/image_module_abi.h"

namespace nightcap {
namespace fs = std::filesystem;

namespace {

struct Module {
  nightcap_images_decode_rgba8_fn decode = nullptr;
  nightcap_images_write_png_rgba8_fn write_png = nullptr;
};

// $NIGHTCAP_IMAGES_MODULE when set, and only it (tests point it elsewhere); otherwise next to
// the running executable, where a copied or installed nightcap keeps it, then where this build
// put it, which is what the test programs in build/tests/ find.
std::vector<fs::path> candidates() {
  // Absolute: dlopen would look a bare file name up on the library path instead.
  if (const char* path = std::getenv("NIGHTCAP_IMAGES_MODULE"); path && *path) return {fs::absolute(path)};
  std::vector<fs::path> paths;
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) paths.push_back(exe.parent_path() / NIGHTCAP_IMAGES_MODULE_NAME);
  if (paths.empty() || paths.front() != fs::path(NIGHTCAP_IMAGES_MODULE_BUILT))
    paths.push_back(NIGHTCAP_IMAGES_MODULE_BUILT);
  return paths;
}

Module load_module() {
  std::string tried;
  for (const fs::path& path : candidates()) {
    if (!fs::exists(path)) {
      tried += (tried.empty() ? "" : ", ") + path.string();
      continue;
    }
    // Never closed: OpenImageIO keeps state (plugins, threads) until the process exits.
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) throw ImageError("cannot load the image module " + path.string() + ": " + ::dlerror());
    auto symbol = [&](const char* name) {
      void* address = ::dlsym(handle, name);
      if (!address) throw ImageError("image module " + path.string() + " lacks " + name + ": " + ::dlerror());
      return address;
    };
    const int abi = reinterpret_cast<nightcap_images_abi_fn>(symbol("nightcap_images_abi"))();
    if (abi != NIGHTCAP_IMAGES_ABI)
      throw ImageError("image module " + path.string() + " has interface version " + std::to_string(abi) +
                       ", this nightcap needs " + std::to_string(NIGHTCAP_IMAGES_ABI) + " (it is from another build)");
    return {reinterpret_cast<nightcap_images_decode_rgba8_fn>(symbol("nightcap_images_decode_rgba8")),
            reinterpret_cast<nightcap_images_write_png_rgba8_fn>(symbol("nightcap_images_write_png_rgba8"))};
  }
  if (const char* path = std::getenv("NIGHTCAP_IMAGES_MODULE"); path && *path)
    throw ImageError("cannot find the image module " + tried + " (named by NIGHTCAP_IMAGES_MODULE)");
  throw ImageError("cannot find the image module " + std::string(NIGHTCAP_IMAGES_MODULE_NAME) + " (looked at " + tried +
                   "; NIGHTCAP_IMAGES_MODULE may name it)");
}

const Module& module() {
  // Thread-safe, and retried on the next call if loading threw.
  static const Module loaded = load_module();
  return loaded;
}

uint8_t* allocate(void* context, uint32_t width, uint32_t height) {
  auto* image = static_cast<Rgba8Image*>(context);
  try {
    image->pixels.resize(size_t(width) * height * 4);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
  image->width = width;
  image->height = height;
  return image->pixels.data();
}

Rgba8Image decode(const std::string& name, const uint8_t* bytes, size_t size, uint32_t max_side) {
  const Module& m = module();
  Rgba8Image image;
  char error[1024];
  if (m.decode(name.c_str(), bytes, size, max_side, allocate, &image, error, sizeof error) != 0)
    throw ImageError(error);
  return image;
}

}  // namespace

Rgba8Image decode_image_file(const fs::path& file, uint32_t max_side) {
  return decode(file.string(), nullptr, 0, max_side);
}

Rgba8Image decode_image_memory(const std::string& name, std::span<const uint8_t> bytes, uint32_t max_side) {
  // A null pointer would mean "read the file `name`".
  static const uint8_t empty = 0;
  return decode(name, bytes.empty() ? &empty : bytes.data(), bytes.size(), max_side);
}

void write_png(const fs::path& file, std::span<const uint8_t> rgba8, uint32_t width, uint32_t height) {
  if (rgba8.size() != size_t(width) * height * 4)
    throw std::logic_error("write_png: " + file.string() + ": pixel count does not match the size");
  const Module& m = module();
  char error[1024];
  if (m.write_png(file.c_str(), rgba8.data(), width, height, error, sizeof error) != 0) throw ImageError(error);
}

}  // namespace nightcap
