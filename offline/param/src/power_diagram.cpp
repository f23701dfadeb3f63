// ngi offline: power diagram of weighted points clipped to the unit square (paper Algorithm 1,
// "Compute the power diagram D(h) / the dual power Delaunay triangulation T(h) / the cell
// areas w(h)"; Aurenhammer 1987, "Power diagrams"). The regular triangulation T(h) comes from
// CGAL::Regular_triangulation_2 (the only CGAL translation unit of ngi_param); each cell is
// then the square clipped by the half-planes
//     y . d_ij <= (|d_ij|^2 + h_i - h_j) / 2,   y = x - p_i,  d_ij = p_j - p_i,
// for every neighbour j of i in T(h). Facet lengths feed the Hessian of Eq. 6.
#include "ngi/param/power_diagram.h"

#include "ngi/error.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Regular_triangulation_face_base_2.h>
#include <CGAL/Regular_triangulation_vertex_base_2.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <thread>
#include <utility>

namespace ngi {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase =
    CGAL::Triangulation_vertex_base_with_info_2<uint32_t, Kernel, CGAL::Regular_triangulation_vertex_base_2<Kernel>>;
using FaceBase = CGAL::Regular_triangulation_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using RegularTriangulation = CGAL::Regular_triangulation_2<Kernel, Tds>;
using WeightedPoint = RegularTriangulation::Weighted_point;

constexpr int32_t kBorder = -1;

struct PolygonVertex {
    glm::dvec2 position;
    int32_t edgeLabel;  // what the edge from this vertex to the next lies on: a neighbour or the border
};

// Clips the convex polygon `in` by { y : y . d <= c }, labelling the new edge `label`.
void clipByHalfPlane(const std::vector<PolygonVertex>& in, glm::dvec2 d, double c, int32_t label,
                     std::vector<PolygonVertex>& out)
{
    out.clear();
    const size_t count = in.size();
    for (size_t k = 0; k < count; ++k) {
        const PolygonVertex& cur = in[k];
        const PolygonVertex& nxt = in[(k + 1) % count];
        const double fc = cur.position.x * d.x + cur.position.y * d.y - c;
        const double fn = nxt.position.x * d.x + nxt.position.y * d.y - c;
        const bool curInside = fc <= 0.0, nextInside = fn <= 0.0;
        if (curInside) out.push_back(cur);
        if (curInside != nextInside) {
            const double t = fc / (fc - fn);
            const glm::dvec2 x = cur.position + t * (nxt.position - cur.position);
            // Leaving: the new edge runs along the bisector; entering: the rest of the old edge.
            out.push_back({x, curInside ? label : cur.edgeLabel});
        }
    }
}

}  // namespace

PowerCells computePowerCells(std::span<const glm::dvec2> sites, std::span<const double> heights, bool withFacets,
                             unsigned threads)
{
    const size_t n = sites.size();
    if (heights.size() != n) throw Error("power diagram: heights and sites differ in size");
    std::vector<std::pair<WeightedPoint, uint32_t>> points;
    points.reserve(n);
    for (size_t i = 0; i < n; ++i)
        points.emplace_back(WeightedPoint(Kernel::Point_2(sites[i].x, sites[i].y), heights[i]), uint32_t(i));
    RegularTriangulation triangulation;
    triangulation.insert(points.begin(), points.end());

    // Neighbours of every site in T(h), as compressed rows (hidden sites have none).
    std::vector<uint32_t> degree(n + 1, 0);
    std::vector<uint8_t> present(n, 0);
    for (auto v = triangulation.finite_vertices_begin(); v != triangulation.finite_vertices_end(); ++v)
        present[v->info()] = 1;
    for (auto e = triangulation.finite_edges_begin(); e != triangulation.finite_edges_end(); ++e) {
        ++degree[e->first->vertex(RegularTriangulation::cw(e->second))->info() + 1];
        ++degree[e->first->vertex(RegularTriangulation::ccw(e->second))->info() + 1];
    }
    for (size_t i = 0; i < n; ++i) degree[i + 1] += degree[i];
    std::vector<uint32_t> neighbours(degree[n]);
    {
        std::vector<uint32_t> fill(degree.begin(), degree.end() - 1);
        for (auto e = triangulation.finite_edges_begin(); e != triangulation.finite_edges_end(); ++e) {
            const uint32_t a = e->first->vertex(RegularTriangulation::cw(e->second))->info();
            const uint32_t b = e->first->vertex(RegularTriangulation::ccw(e->second))->info();
            neighbours[fill[a]++] = b;
            neighbours[fill[b]++] = a;
        }
    }
    // CGAL's edge order follows where its faces landed in memory, which differs from call to
    // call (and run to run); the clipping below rounds differently in a different order, and
    // Newton amplifies that into different bakes of the same mesh (boeing at 1024: refused by
    // the image check in one run, 0% in the next). In index order the cells are reproducible.
    for (size_t i = 0; i < n; ++i) std::sort(neighbours.begin() + degree[i], neighbours.begin() + degree[i + 1]);

    PowerCells cells;
    cells.area.assign(n, 0.0);
    cells.centroid.assign(sites.begin(), sites.end());
    std::vector<std::vector<PowerFacet>> facetsPerThread(std::max(1u, threads));
    auto clipRange = [&](unsigned thread, size_t begin, size_t end) {
        std::vector<PolygonVertex> polygon, scratch;
        std::vector<PowerFacet>& facets = facetsPerThread[thread];
        for (size_t i = begin; i < end; ++i) {
            if (!present[i]) continue;
            const glm::dvec2 p = sites[i];
            polygon = {{{-p.x, -p.y}, kBorder},
                       {{1 - p.x, -p.y}, kBorder},
                       {{1 - p.x, 1 - p.y}, kBorder},
                       {{-p.x, 1 - p.y}, kBorder}};
            for (uint32_t k = degree[i]; k < degree[i + 1] && !polygon.empty(); ++k) {
                const uint32_t j = neighbours[k];
                const glm::dvec2 d = sites[j] - p;
                const double c = 0.5 * (d.x * d.x + d.y * d.y + heights[i] - heights[j]);
                clipByHalfPlane(polygon, d, c, int32_t(j), scratch);
                polygon.swap(scratch);
            }
            if (polygon.size() < 3) continue;
            double twiceArea = 0.0;
            glm::dvec2 moment(0.0);
            for (size_t k = 0; k < polygon.size(); ++k) {
                const glm::dvec2 a = polygon[k].position, b = polygon[(k + 1) % polygon.size()].position;
                const double cross = a.x * b.y - a.y * b.x;
                twiceArea += cross;
                moment += cross * (a + b);
                if (withFacets && polygon[k].edgeLabel > int32_t(i)) {
                    const double length = std::sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
                    const uint32_t j = uint32_t(polygon[k].edgeLabel);
                    if (length > 0.0)
                        facets.push_back({uint32_t(i), j, length,
                                          std::sqrt((sites[j].x - p.x) * (sites[j].x - p.x) +
                                                    (sites[j].y - p.y) * (sites[j].y - p.y))});
                }
            }
            if (twiceArea <= 0.0) continue;
            cells.area[i] = 0.5 * twiceArea;
            cells.centroid[i] = p + moment / (3.0 * twiceArea);
        }
    };
    const unsigned threadCount = std::max(1u, threads);
    std::vector<std::thread> workers;
    for (unsigned t = 1; t < threadCount; ++t)
        workers.emplace_back(clipRange, t, n * t / threadCount, n * (t + 1) / threadCount);
    clipRange(0, 0, n / threadCount);
    for (std::thread& w : workers) w.join();

    for (size_t i = 0; i < n; ++i)
        if (!(cells.area[i] > 0.0)) ++cells.emptyCells;
    if (withFacets)
        for (auto& facets : facetsPerThread) cells.facets.insert(cells.facets.end(), facets.begin(), facets.end());
    return cells;
}

}  // namespace ngi
