# ngi_embed_shaders(): the one build rule for GLSL in ngi (the engine's shaders/ and the
# viewer's engine/viewer/shaders/). Each source is compiled to SPIR-V by glslangValidator
# (Vulkan 1.2), checked by spirv-val and embedded by embed_spirv.cmake as a C++ header
# HEADER_DIR/<name with '.' -> '_'>.h defining `inline constexpr uint32_t <ident>_spv[]`,
# so nothing is loaded at run time.
#
#   ngi_embed_shaders(TARGET <custom target that builds every header>
#                     SOURCE_DIR <dir of the sources> HEADER_DIR <dir of the generated headers>
#                     SOURCES <file>...
#                     [INCLUDE_DIRS <dir>...]   # -I for #include (GL_GOOGLE_include_directive)
#                     [DEPENDS <file>...])      # included files: any change recompiles every source
include_guard(GLOBAL)

find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
find_program(SPIRV_VAL spirv-val REQUIRED)

function(ngi_embed_shaders)
  cmake_parse_arguments(S "" "TARGET;SOURCE_DIR;HEADER_DIR" "SOURCES;INCLUDE_DIRS;DEPENDS" ${ARGN})
  if(NOT S_TARGET OR NOT S_SOURCE_DIR OR NOT S_HEADER_DIR OR NOT S_SOURCES)
    message(FATAL_ERROR "ngi_embed_shaders: TARGET, SOURCE_DIR, HEADER_DIR and SOURCES are required")
  endif()
  set(embed ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/embed_spirv.cmake)
  set(include_flags)
  foreach(dir ${S_INCLUDE_DIRS})
    list(APPEND include_flags -I${dir})
  endforeach()
  set(headers)
  foreach(src ${S_SOURCES})
    string(REPLACE "." "_" ident ${src})
    set(spv ${CMAKE_CURRENT_BINARY_DIR}/${src}.spv)
    set(hdr ${S_HEADER_DIR}/${ident}.h)
    add_custom_command(
      OUTPUT ${hdr}
      COMMAND ${GLSLANG_VALIDATOR} --quiet -V --target-env vulkan1.2 ${include_flags} -o ${spv} ${S_SOURCE_DIR}/${src}
      COMMAND ${SPIRV_VAL} --target-env vulkan1.2 ${spv}
      COMMAND ${CMAKE_COMMAND} -DSPV=${spv} -DHEADER=${hdr} -DIDENT=${ident} -P ${embed}
      DEPENDS ${S_SOURCE_DIR}/${src} ${S_DEPENDS} ${embed}
      COMMENT "Compiling shader ${src}"
      VERBATIM)
    list(APPEND headers ${hdr})
  endforeach()
  add_custom_target(${S_TARGET} DEPENDS ${headers})
endfunction()
