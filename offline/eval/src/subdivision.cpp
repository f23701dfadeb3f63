// ngi offline eval, peers: Loop (1987) and modified Butterfly (Zorin et al. 1996) subdivision
// through OpenMesh's uniform subdividers.
#include "ngi/eval/subdivision.h"

#include "ngi/error.h"
#include "surface_checks.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/ModifiedButterFlyT.hh>

namespace ngi {
namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// OpenMesh reports refused faces on omerr(); library code prints nothing (STYLE.md 11).
class QuietOpenMesh {
public:
    QuietOpenMesh() : wasEnabled_(omerr().is_enabled()) { omerr().disable(); }
    ~QuietOpenMesh()
    {
        if (wasEnabled_) omerr().enable();
    }
    QuietOpenMesh(const QuietOpenMesh&) = delete;
    QuietOpenMesh& operator=(const QuietOpenMesh&) = delete;

private:
    bool wasEnabled_;
};

}  // namespace

SubdivisionResult subdivideMesh(const TriangleMesh& mesh, const SubdivisionOptions& options)
{
    detail::checkSurface(mesh, "subdivide: mesh");
    if (options.iterations > 6)
        throw Error("subdivide: at most 6 iterations (4^6 x the triangles), got " + std::to_string(options.iterations));

    SubdivisionResult result;
    OmMesh om;
    {
        QuietOpenMesh quiet;
        std::vector<OmMesh::VertexHandle> vertices;
        vertices.reserve(mesh.positions.size());
        for (const glm::dvec3& p : mesh.positions) vertices.push_back(om.add_vertex(OmMesh::Point(p.x, p.y, p.z)));
        for (const glm::uvec3& t : mesh.triangles) {
            if (t.x == t.y || t.y == t.z || t.z == t.x) continue;
            if (om.add_face(vertices[t.x], vertices[t.y], vertices[t.z]).is_valid()) continue;
            // A non-manifold configuration: subdivide this triangle as its own piece.
            ++result.detachedTriangles;
            OmMesh::VertexHandle v[3];
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3& p = mesh.positions[t[k]];
                v[k] = om.add_vertex(OmMesh::Point(p.x, p.y, p.z));
            }
            om.add_face(v[0], v[1], v[2]);
        }
    }
    if (om.n_faces() == 0) throw Error("subdivide: mesh has no proper triangle");

    if (options.iterations > 0) {
        bool ok = false;
        if (options.scheme == SubdivisionScheme::loop) {
            OpenMesh::Subdivider::Uniform::LoopT<OmMesh, double> loop;
            loop.attach(om);
            ok = loop(options.iterations);
            loop.detach();
        } else {
            OpenMesh::Subdivider::Uniform::ModifiedButterflyT<OmMesh, double> butterfly;
            butterfly.attach(om);
            ok = butterfly(options.iterations);
            butterfly.detach();
        }
        if (!ok) throw Error("subdivide: OpenMesh's subdivider failed");
    }

    // Vertices without a face (isolated input vertices) are left out.
    std::vector<uint32_t> index(om.n_vertices(), UINT32_MAX);
    for (const auto& f : om.faces()) {
        glm::uvec3 t;
        int k = 0;
        for (const auto& v : f.vertices()) {
            uint32_t& i = index[v.idx()];
            if (i == UINT32_MAX) {
                i = uint32_t(result.mesh.positions.size());
                const OmMesh::Point& p = om.point(v);
                result.mesh.positions.push_back({p[0], p[1], p[2]});
            }
            t[k++] = i;
        }
        result.mesh.triangles.push_back(t);
    }
    return result;
}

}  // namespace ngi
