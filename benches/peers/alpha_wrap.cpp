// Peer for side-by-side timing (issue 16): CGAL's 3D Alpha Wrapping on a point cloud or a
// triangle soup. Built by benches/peers/build.sh from Debian's header-only libcgal-dev; never a
// dependency of LSW. Usage: alpha_wrap IN OUT [alpha_div=20] [offset_div=600]
// ("coarse" = alpha diagonal/20, offset diagonal/600). Prints one JSON line with the times.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/IO/read_points.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: alpha_wrap IN OUT [alpha_div=20] [offset_div=600]\n";
    return 2;
  }
  const std::string in = argv[1], out = argv[2];
  const double alpha_div = argc > 3 ? std::stod(argv[3]) : 20.0;
  const double offset_div = argc > 4 ? std::stod(argv[4]) : 600.0;
  auto t0 = std::chrono::steady_clock::now();
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> faces;
  // A soup with faces is wrapped as triangles; without faces as points.
  if (!CGAL::IO::read_polygon_soup(in, points, faces) || faces.empty()) {
    points.clear();
    faces.clear();
    if (!CGAL::IO::read_points(in, std::back_inserter(points)) || points.empty()) {
      std::cerr << "cannot read " << in << "\n";
      return 1;
    }
  }
  auto t1 = std::chrono::steady_clock::now();
  CGAL::Bbox_3 bb = CGAL::bbox_3(points.begin(), points.end());
  const double diag = std::sqrt(CGAL::square(bb.xmax() - bb.xmin()) +
                                CGAL::square(bb.ymax() - bb.ymin()) +
                                CGAL::square(bb.zmax() - bb.zmin()));
  Mesh wrap;
  if (faces.empty())
    CGAL::alpha_wrap_3(points, diag / alpha_div, diag / offset_div, wrap);
  else
    CGAL::alpha_wrap_3(points, faces, diag / alpha_div, diag / offset_div, wrap);
  auto t2 = std::chrono::steady_clock::now();
  CGAL::IO::write_polygon_mesh(out, wrap, CGAL::parameters::stream_precision(17));
  auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  std::cout << "{\"read_ms\":" << ms(t0, t1) << ",\"wrap_ms\":" << ms(t1, t2)
            << ",\"vertices\":" << num_vertices(wrap) << ",\"faces\":" << num_faces(wrap)
            << ",\"input_points\":" << points.size() << ",\"input_faces\":" << faces.size() << "}\n";
  return 0;
}
