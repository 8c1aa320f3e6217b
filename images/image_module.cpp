// The image module: the only code of nightcap that links OpenImageIO (see image_module_abi.h).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstring>
#include <string>
#include <vector>

#include "images/image_module_abi.h"

namespace {

int report(const std::string& message, char* error, size_t error_size) {
  if (error_size > 0) {
    const size_t n = std::min(message.size(), error_size - 1);
    std::memcpy(error, message.data(), n);
    error[n] = '\0';
  }
  return 1;
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int nightcap_images_abi() { return NIGHTCAP_IMAGES_ABI; }

__attribute__((visibility("default"))) int nightcap_images_decode_rgba8(const char* name, const uint8_t* bytes,
                                                                        size_t size, uint32_t max_side,
                                                                        nightcap_images_allocate_fn allocate,
                                                                        void* context, char* error, size_t error_size) {
  try {
    // Outlives `input`, which reads through it. Passed as an argument: OpenImageIO 2.4's open()
    // does not look for the "oiio:ioproxy" configuration hint and tries to open `name` as a file.
    OIIO::Filesystem::IOMemReader reader(bytes, size);
    auto input = OIIO::ImageInput::open(name, nullptr, bytes ? &reader : nullptr);
    if (!input) return report(OIIO::geterror(), error, error_size);
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || uint32_t(spec.width) > max_side || uint32_t(spec.height) > max_side ||
        spec.nchannels < 1 || spec.nchannels > 16)
      return report("image size " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + "x" +
                        std::to_string(spec.nchannels) + " not supported",
                    error, error_size);
    const int channels = spec.nchannels;
    const size_t texels = size_t(spec.width) * size_t(spec.height);
    std::vector<uint8_t> pixels(texels * channels);
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, pixels.data()))
      return report(input->geterror(), error, error_size);
    uint8_t* out = allocate(context, uint32_t(spec.width), uint32_t(spec.height));
    if (!out) return report("out of memory for the decoded image", error, error_size);
    for (size_t i = 0; i < texels; ++i) {
      const uint8_t* p = &pixels[i * channels];
      uint8_t* q = &out[i * 4];
      if (channels < 3) {
        q[0] = q[1] = q[2] = p[0];
        q[3] = channels == 2 ? p[1] : 255;
      } else {
        q[0] = p[0];
        q[1] = p[1];
        q[2] = p[2];
        q[3] = channels >= 4 ? p[3] : 255;
      }
    }
    return 0;
  } catch (const std::exception& e) {
    // Nothing may unwind into the caller through the C interface.
    return report(e.what(), error, error_size);
  }
}

__attribute__((visibility("default"))) int nightcap_images_write_png_rgba8(const char* file, const uint8_t* rgba8,
                                                                           uint32_t width, uint32_t height, char* error,
                                                                           size_t error_size) {
  try {
    auto out = OIIO::ImageOutput::create("png");
    const OIIO::ImageSpec spec(int(width), int(height), 4, OIIO::TypeDesc::UINT8);
    if (!out) return report(OIIO::geterror(), error, error_size);
    if (!out->open(file, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgba8) || !out->close())
      return report(out->geterror(), error, error_size);
    return 0;
  } catch (const std::exception& e) {
    return report(e.what(), error, error_size);
  }
}
}
