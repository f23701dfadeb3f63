#version 450
// The host's material for ngi's surfaces, drawn one LoD per instance (DrawBatch) or adaptively:
// ngi_lit.glsl.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#define HOST_LIGHT_SET NGI_DRAW_HOST_SET
#include "lighting.glsl"
#include "ngi_lit.glsl"
