/***************************************************************************
  linevisibility.h - a map line in a photo, its hidden parts marked
  -------------------------------------------------------------------------
  For showing any map layer in an oriented photo (Stokes (1988)'s
  map-to-image direction): the line is densified so it follows its curve
  in the photo (heights of inserted points from the DEM, or interpolated),
  every point is projected and tested against the terrain, and the line
  comes back as runs, each wholly visible or wholly hidden behind the
  terrain. Neighbouring runs share their boundary point, so the drawn line
  has no gaps; a point behind the camera ends a run.
 ***************************************************************************/
#ifndef GEOSTATION_DEM_LINEVISIBILITY_H
#define GEOSTATION_DEM_LINEVISIBILITY_H

#include <vector>

#include <Eigen/Core>

#include "dem/monoplotter.h"

namespace geostation
{

  struct LineVisibilityRun
  {
    std::vector<Eigen::Vector2d> pixels; //!< (col, row), at least two
    bool hidden = false;                 //!< in the frame but behind the terrain
  };

  /**
   * The runs of a map polyline (block CRS, metres, with heights) in the
   * image. `monoplotter` (may be null: nothing is hidden) gives the terrain
   * test and the heights of inserted points. Points outside the frame count
   * as visible (they are not hidden, only not on the photo). Throws
   * std::invalid_argument if densifyPx <= 0.
   */
  std::vector<LineVisibilityRun> lineVisibilityRuns( const OrientedImage &image, const Monoplotter *monoplotter, const std::vector<Eigen::Vector3d> &vertices,
      double densifyPx = 2.0 );

} // namespace geostation

#endif // GEOSTATION_DEM_LINEVISIBILITY_H
