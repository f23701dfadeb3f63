#version 450
// ngi's fragment shader for the uniform draw (surface.vert): surface_shading.glsl with the
// default grey material.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "surface_shading.glsl"
