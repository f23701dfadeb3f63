// ngi offline: the one translation unit that compiles tinygltf's implementation (see
// mesh_io_tinygltf.h for why it is ours and not Debian's shared library).
#define TINYGLTF_IMPLEMENTATION
#include "mesh_io_tinygltf.h"
