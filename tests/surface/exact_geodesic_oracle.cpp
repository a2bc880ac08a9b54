// The test oracle of the surface specifications: exact polyhedral geodesic
// distances from one vertex of a triangle mesh to all its vertices, computed
// by CGAL's Surface_mesh_shortest_path (an exact method on the triangles'
// geometry, in double precision).
//
// CGAL is licensed under the GPL. This program is built only with the tests
// (STVD_BUILD_TESTS, when CGAL is found), links nothing of stvd, is never
// installed, and talks to the tests through files: the library, the tool and
// every installed target stay under the BSD 3-Clause licence.
//
// Usage: stvd_exact_geodesic_oracle MESH.off SOURCE_VERTEX OUTPUT
// OUTPUT gets one line per vertex, in file order: the distance (%.17g).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_shortest_path.h>
#include <CGAL/boost/graph/IO/OFF.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Traits = CGAL::Surface_mesh_shortest_path_traits<Kernel, Mesh>;
using ShortestPath = CGAL::Surface_mesh_shortest_path<Traits>;

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: stvd_exact_geodesic_oracle MESH.off SOURCE_VERTEX OUTPUT\n";
    return 2;
  }
  Mesh mesh;
  std::ifstream in(argv[1]);
  if (!in || !CGAL::IO::read_OFF(in, mesh) || mesh.is_empty() || !CGAL::is_triangle_mesh(mesh)) {
    std::cerr << argv[1] << ": not a triangle mesh in OFF format that CGAL can read\n";
    return 3;
  }
  const long source = std::strtol(argv[2], nullptr, 10);
  if (source < 0 || source >= static_cast<long>(mesh.number_of_vertices())) {
    std::cerr << argv[1] << ": no vertex " << argv[2] << "\n";
    return 4;
  }
  ShortestPath paths(mesh);
  paths.add_source_point(Mesh::Vertex_index(static_cast<Mesh::size_type>(source)));
  paths.build_sequence_tree();
  const std::string temporary = std::string(argv[3]) + ".part";
  std::FILE* out = std::fopen(temporary.c_str(), "w");
  if (!out) {
    std::cerr << argv[3] << ": cannot be written\n";
    return 5;
  }
  for (const Mesh::Vertex_index v : mesh.vertices())
    std::fprintf(out, "%.17g\n", paths.shortest_distance_to_source_points(v).first);
  if (std::fclose(out) != 0 || std::rename(temporary.c_str(), argv[3]) != 0) {
    std::cerr << argv[3] << ": cannot be written\n";
    return 5;
  }
  return 0;
}
