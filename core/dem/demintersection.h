/***************************************************************************
  demintersection.h - the first intersection of a ray with a DEM
  -------------------------------------------------------------------------
  A DEM in the block's own CRS is traversed exactly: the ray is straight in
  the DEM's grid, so it walks tiles, 8 x 8 blocks and cells in turn, passes
  over every tile and block whose highest corner it stays above, and solves
  each remaining cell's bilinear patch for the crossing (along the ray the
  height above the patch is a quadratic). Unfilled holes are taken to reach
  up to the highest terrain of their tile: a ray that comes that low over a
  hole reports it.
  A DEM in another CRS (e.g. geographic) curves the ray in its grid: it is
  followed chord by chord, each chord's ends transformed exactly by PROJ and
  chords short enough to stay within 0.05 mm of the curve, and the crossing
  found on a chord is refined on the exact curve by false position to
  0.1 mm along the ray.
  Both work for nadir rays and for grazing rays from a camera near the
  ground, where the iterative height update of Stokes (1988)
  diverges.
 ***************************************************************************/
#ifndef GEOSTATION_DEM_DEMINTERSECTION_H
#define GEOSTATION_DEM_DEMINTERSECTION_H

#include <functional>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "dem/dem.h"
#include "geometry/crs.h"
#include "geometry/projection.h"
#include "geometry/windowshape.h"

namespace geostation
{

  struct DemIntersectionOptions
  {
    double maxRangeM = 100000.0; //!< give up beyond this distance along the ray
    double toleranceM = 1e-4;    //!< refinement on a curved ray stops within this (metres along the ray, or height above the DEM)
  };

  struct DemIntersection
  {
    enum class Status
    {
      Hit,
      Miss,            //!< the ray leaves the DEM, or runs out of range, without meeting it
      BelowSurface,    //!< the ray starts below the terrain
      Hole,            //!< the ray meets a hole too large to fill
    };
    Status status = Status::Miss;
    std::string message;
    Eigen::Vector3d point = Eigen::Vector3d::Zero(); //!< block CRS
    double rangeM = 0.0;
    int steps = 0;                 //!< tiles, blocks and cells visited

    bool hit() const { return status == Status::Hit; }
  };

  /**
   * A per-feature status name for batch outputs (issue-free runs report
   * "ok"): "ok" (Hit), "misses_dem" (the ray leaves the DEM or runs out of
   * range), "below_dem" (it starts below the terrain), "dem_hole" (a hole
   * too large to fill).
   */
  std::string demIntersectionStatusName( DemIntersection::Status status );

  /**
   * Intersects a ray given in the block CRS with the DEM. `blockToDem` maps
   * block coordinates to the DEM's CRS (identity when they agree).
   */
  DemIntersection intersectRayWithDem( const Ray &ray, const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options = DemIntersectionOptions() );

  /**
   * The DEM as a surface for any oriented image: a pixel's ray intersected
   * with it (e.g. to predict matching windows' shapes). The DEM and the
   * transform are referenced, not copied: they must outlive the function.
   */
  GroundOfPixel demGroundOfPixel( const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options = DemIntersectionOptions() );

  /**
   * The DEM's height at a point (x, y) of the block CRS (e.g. the terrain
   * of a stereo pair's mapping); nothing outside the DEM or in a hole. The
   * DEM and the transform are referenced: they must outlive the function.
   */
  std::function<std::optional<double>( double x, double y )> demHeightAt( const Dem &dem, const CrsTransform &blockToDem );

} // namespace geostation

#endif // GEOSTATION_DEM_DEMINTERSECTION_H
