// PCL peer of hg-bench: pcl::ConcaveHull in 2-D. Its alpha is a circumradius: a qhull Delaunay triangle
// is kept when the distance from its Voronoi centre to its vertices is <= alpha (concave_hull.hpp), so
// setAlpha(R) is our R.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/concave_hull.h>

#include <vector>

#include "peers.hpp"

namespace hg::bench {

PeerOutline pcl_concave_hull(std::span<const outline::Vec2> points, double R) {
  PeerOutline out;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    (*cloud)[i] = pcl::PointXYZ(static_cast<float>(points[i].x), static_cast<float>(points[i].y), 0.0f);
  pcl::ConcaveHull<pcl::PointXYZ> hull;
  hull.setInputCloud(cloud);
  hull.setAlpha(R);
  hull.setDimension(2);
  hull.setKeepInformation(false);
  pcl::PointCloud<pcl::PointXYZ> hull_points;
  std::vector<pcl::Vertices> polygons;
  hull.reconstruct(hull_points, polygons);
  // PCL neither orients its polygons consistently nor separates holes: count loops and their vertices.
  for (const auto& poly : polygons) {
    out.boundary_edges += poly.vertices.size();
    ++out.outer_loops;
  }
  return out;
}

}  // namespace hg::bench
