// ngi offline: tinygltf, compiled into ngi_mesh under a namespace of its own (private).
//
// Why not Debian's libtinygltf.so: libdraco.so (linked by ngi_eval) exports its own,
// different build of tinygltf::TinyGLTF::LoadASCIIFromFile & co. In ngi-eval the dynamic
// linker bound our calls to draco's copy, whose object layout differs, and every glTF read
// failed with "FS callback not set". Compiled here as ngi_tinygltf, the calls bind to this
// copy in every program, whatever else is linked. Images are never decoded (only geometry
// is read), so stb_image is left out.
#pragma once

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#define tinygltf ngi_tinygltf
#include <tiny_gltf.h>
#undef tinygltf
