/***************************************************************************
  gridwalk.h - walking a straight ray through a DEM's grid (internal)
  -------------------------------------------------------------------------
  The pieces of the exact ray / DEM traversal shared by the single-ray and
  the batch intersections: the ray in grid coordinates, the crossing with
  one cell's bilinear patch, and the walk over tiles, blocks and cells.
 ***************************************************************************/
#ifndef GEOSTATION_DEM_GRIDWALK_H
#define GEOSTATION_DEM_GRIDWALK_H

#include <limits>
#include <optional>

#include <Eigen/Core>

#include "dem/dem.h"

namespace geostation::gridwalk
{
  constexpr double kInf = std::numeric_limits<double>::infinity();

  //! The ray in the DEM's cell-centre grid: (u, v) = pixel - 0.5, so vertex (i, j) sits at (i, j); z in height units.
  struct GridRay
  {
    double u0, v0, z0, du, dv, dz;
    double invDu, invDv, invDz; //!< 1 / du etc., infinite for 0
    double u( double t ) const { return u0 + t * du; }
    double v( double t ) const { return v0 + t * dv; }
    double z( double t ) const { return z0 + t * dz; }
  };

  struct GridWalk
  {
    std::optional<double> hit; //!< range of the first crossing
    bool hole = false;
    int steps = 0;
  };

  /**
   * The first crossing of the ray with the bilinear patch of cell (i, j),
   * corners h00 (i, j), h10 (i + 1, j), h01 (i, j + 1), h11, over
   * [ta, tb]; nothing if the ray stays above it there.
   */
  std::optional<double> crossingInCell( const GridRay &ray, int i, int j, double h00, double h10, double h01, double h11, double ta, double tb );

  //! The straight grid ray through two grid points (u, v) at ranges ta < tb of the block ray, z from the block ray.
  GridRay chord( const Eigen::Vector2d &a, const Eigen::Vector2d &b, double ta, double tb, double z0, double dz );

  /**
   * Shortens [t0, t1] to where the grid ray is over the cell-centre area
   * [0, W - 1] x [0, H - 1]; false if it is nowhere over it. `exits` tells
   * whether t1 was shortened.
   */
  bool clipToDem( const GridRay &g, const Dem &dem, double &t0, double &t1, bool &exits );

  /**
   * Walks tiles, blocks and cells along the straight grid ray over [t0, t1]
   * (over the DEM): tiles and blocks whose highest corner the ray stays
   * above are passed over, the remaining cells solved exactly.
   */
  GridWalk walkGrid( const GridRay &g, const Dem &dem, double t0, double t1 );

  //! (u, v) grid coordinates of a point in the DEM's CRS.
  Eigen::Vector2d gridPoint( const Dem &dem, const Eigen::Vector3d &inDem );
}

#endif // GEOSTATION_DEM_GRIDWALK_H
