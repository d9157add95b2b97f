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
  A DEM in another CRS (the ray is curved in its grid) is marched with steps
  that cannot jump over the surface: the height above the terrain h shrinks
  at most by (|dz| + S |dxy|) per metre of ray, S the local slope bound of
  the DEM, so a step of h / (|dz| + S |dxy|) stays above it; near the
  surface steps of a quarter cell take over (two crossings closer together
  than that count as one). When a step ends below the surface, the crossing
  is found by false position (Illinois) on the bilinear surface, to 0.1 mm
  along the ray.
  Both work for nadir rays and for grazing rays from a camera near the
  ground, where the iterative height update of the monoplotter paper
  diverges.
 ***************************************************************************/
#ifndef GEOSTATION_DEM_DEMINTERSECTION_H
#define GEOSTATION_DEM_DEMINTERSECTION_H

#include <string>

#include <Eigen/Core>

#include "dem/dem.h"
#include "geometry/crs.h"
#include "geometry/projection.h"

namespace geostation
{

  struct DemIntersectionOptions
  {
    double maxRangeM = 100000.0; //!< give up beyond this distance along the ray
    double toleranceM = 1e-4;    //!< the march's false position stops when the bracket is this short (along the ray)
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
    int steps = 0;                 //!< tiles, blocks and cells visited, or march steps

    bool hit() const { return status == Status::Hit; }
  };

  /**
   * Intersects a ray given in the block CRS with the DEM. `blockToDem` maps
   * block coordinates to the DEM's CRS (identity when they agree).
   */
  DemIntersection intersectRayWithDem( const Ray &ray, const Dem &dem, const CrsTransform &blockToDem, const DemIntersectionOptions &options = DemIntersectionOptions() );

} // namespace geostation

#endif // GEOSTATION_DEM_DEMINTERSECTION_H
