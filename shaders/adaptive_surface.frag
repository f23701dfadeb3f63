#version 450
// ngi's fragment shader for the adaptive draw (adaptive_surface.vert): surface_shading.glsl
// with the chart's base colour image (set NGI_ADAPTIVE_SET_LEVELS, binding 2).
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#define NGI_BASE_COLOUR 1
#include "surface_shading.glsl"
