# Turns a SPIR-V binary into a C++ header: inline constexpr uint32_t <IDENT>_spv[] = {...};
file(READ ${SPV} hex HEX)
# SPIR-V words are little-endian: reverse the 4 bytes of each word.
string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1u,\n" body "${hex}")
file(WRITE ${HEADER} "// Generated from ${SPV}; do not edit.\n#pragma once\n#include <cstdint>\ninline constexpr uint32_t ${IDENT}_spv[] = {\n${body}};\n")
