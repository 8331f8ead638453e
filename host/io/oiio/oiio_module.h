#pragma once
// The C interface of the OpenImageIO module (libsplatcl_oiio.so). OpenImageIO pulls in some 260
// shared libraries, whose relocation cost every splatcl process about 0.25 s at start-up, so the
// program loads it only when it reads or writes an image (host/io/image_codec.cpp).
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

// Encodes width×height RGB floats in [0, 1] (row 0 = bottom) into the format the path's extension
// names (8-bit for PNG and the like, half floats for .exr and .hdr), top row first, and hands the
// bytes to append(sink, ...). Returns 0, or 1 with a message (no file name) in error.
int splatcl_oiio_encode_rgb(const char* path, int width, int height, const float* rgb, void* sink,
                            void (*append)(void* sink, const unsigned char* bytes, size_t size), char* error,
                            size_t error_size);

// Decodes the image at path into 8-bit channels, top row first: allocate(sink, width, height,
// channels) returns the buffer for them. Returns 0, or 1 with a message (no file name) in error.
int splatcl_oiio_decode_u8(const char* path, void* sink,
                           unsigned char* (*allocate)(void* sink, int width, int height, int channels), char* error,
                           size_t error_size);

#ifdef __cplusplus
}
#endif
