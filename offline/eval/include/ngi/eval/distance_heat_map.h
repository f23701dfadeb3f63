// ngi offline eval: a picture of where one surface is far from another (DESIGN.md "Metrics":
// point to surface, in the reference frame's units), for `ngi-eval distance --heat-map` and
// `ngi-eval report`: the reference seen from two sides, each triangle coloured by its distance
// to the candidate on a log scale, so that both the spread and the worst spots show. Part of
// ngi_eval_report (it measures with ngi_param's squaredDistancesToSurface).
#pragma once

#include "ngi/eval/report_picture.h"
#include "ngi/eval/surface_distance.h"
#include "ngi/mesh/triangle_mesh.h"

namespace ngi {

struct DistanceHeatMap {
    RgbImage image;         // two views side by side (yaw 35 and 215 degrees), 512 pixels each
    double redAt = 0.0;     // the distance drawn red (reference frame units)
    double farthest = 0.0;  // the largest distance of a reference triangle to the candidate
};

// Each triangle of `reference` coloured by its distance to `candidate` (the largest over its
// corners and its centroid, times frame.scale): blue at or below redAt / 100, red at or above
// redAt (`redAt` <= 0: the farthest triangle's distance). `threads` >= 1 measure. ngi::Error as
// renderMeshPicture and squaredDistancesToSurface.
DistanceHeatMap distanceHeatMap(const TriangleMesh& reference, const TriangleMesh& candidate,
                                const ReferenceFrame& frame, double redAt, unsigned threads);

}  // namespace ngi
