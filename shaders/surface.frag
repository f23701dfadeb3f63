#version 450
// ngi's fragment shader for the uniform draw (surface.vert): surface_shading.glsl with the
// chart's base colour image (set 0, binding NGI_DRAW_BINDING_BASE_COLOUR; the default grey
// where the chart has none).
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#define NGI_BASE_COLOUR 1
#include "surface_shading.glsl"
