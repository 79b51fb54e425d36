#pragma once
// The C interface of the OpenImageIO module (image_oiio_module.cpp), resolved with dlsym by
// image_io.cpp. Each function returns 1 on success, 0 with a message in `error` otherwise.
#include <cstddef>

extern "C" {

// Receives the encoded image when the format can be written to memory.
typedef void (*RayspaceImageSink)(void* context, const void* data, std::size_t size);

// Whether OpenImageIO writes the format `path`'s extension names.
int rayspace_oiio_can_write(const char* path, char* error, std::size_t capacity);
typedef int (*RayspaceOiioCanWrite)(const char*, char*, std::size_t);

// Encodes 8-bit RGB pixels in the format `name` names: to memory through `sink` (*in_memory = 1), or,
// for a format OpenImageIO cannot encode to memory, into the file `temp_path` (*in_memory = 0).
int rayspace_oiio_write(const char* name, const char* temp_path, int width, int height, const unsigned char* rgb,
                        RayspaceImageSink sink, void* sink_context, int* in_memory, char* error,
                        std::size_t capacity);
typedef int (*RayspaceOiioWrite)(const char*, const char*, int, int, const unsigned char*, RayspaceImageSink, void*,
                                 int*, char*, std::size_t);
}
