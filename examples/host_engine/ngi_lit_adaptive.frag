#version 450
// The host's material for ngi's adaptive draws: ngi_lit.glsl with the chart's base colour.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#define HOST_LIGHT_SET NGI_DRAW_HOST_SET
#include "lighting.glsl"
#define NGI_LIT_BASE_COLOUR 1
#include "ngi_lit.glsl"
