// The C interface between nightcap_core (images/images.cpp) and the image module
// (images/image_module.cpp). The module links OpenImageIO, whose dependency tree (codecs,
// OpenCV, FFmpeg, ...) takes longer to load than most commands take to run; core loads it with
// dlopen only when an image is first decoded or written. Plain C so that nothing but these
// signatures has to match across the boundary.
#pragma once

#include <stddef.h>
#include <stdint.h>

// Bumped whenever a signature below changes, so that a module left over from another build is
// refused with a message instead of being called with the wrong arguments.
#define NIGHTCAP_IMAGES_ABI 1

extern "C" {

// nightcap_images_abi: returns the NIGHTCAP_IMAGES_ABI the module was built with.
typedef int (*nightcap_images_abi_fn)(void);

// Called once the size is known; returns width * height * 4 writable bytes.
typedef uint8_t* (*nightcap_images_allocate_fn)(void* context, uint32_t width, uint32_t height);

// nightcap_images_decode_rgba8: decodes an image to RGBA8 (grey fills RGB, missing alpha is
// opaque). With `bytes` null it reads the file `name`; otherwise it decodes `size` bytes in
// memory and `name`'s extension picks the format. Images with a side over `max_side` are
// refused. Returns 0, or nonzero with a NUL-terminated message in `error`.
typedef int (*nightcap_images_decode_rgba8_fn)(const char* name, const uint8_t* bytes, size_t size, uint32_t max_side,
                                               nightcap_images_allocate_fn allocate, void* context, char* error,
                                               size_t error_size);

// nightcap_images_write_png_rgba8: writes width * height RGBA8 pixels as a PNG. Returns 0, or
// nonzero with a NUL-terminated message in `error`.
typedef int (*nightcap_images_write_png_rgba8_fn)(const char* file, const uint8_t* rgba8, uint32_t width,
                                                  uint32_t height, char* error, size_t error_size);
}
