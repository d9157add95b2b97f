/***************************************************************************
  demcoverage.h - how much of the ground seen in a photo the DEM covers
  -------------------------------------------------------------------------
  Monoplotting places a pixel where its ray meets the DEM; a DEM that does
  not reach the photo's whole footprint (a tile too small, another area, a
  big hole) leaves part of the photo where nothing digitised can be placed.
  The rays of a grid of sample pixels over the frame are intersected with
  the DEM; rays that point at or above the horizon look at the sky and do
  not count. The summary says how much of the ground is covered and where
  in the frame the rest lies, in one sentence for the operator.
 ***************************************************************************/
#ifndef GEOSTATION_DEM_DEMCOVERAGE_H
#define GEOSTATION_DEM_DEMCOVERAGE_H

#include <string>

#include <Eigen/Core>

#include "dem/monoplotter.h"

namespace geostation
{

  struct DemCoverageOptions
  {
    int columns = 12; //!< sample pixels across the frame
    int rows = 9;     //!< sample pixels down the frame

    //! Throws std::invalid_argument unless both are 2 to 200.
    void check() const;
  };

  struct DemCoverageSummary
  {
    int samples = 0;       //!< sample pixels
    int sky = 0;           //!< rays at or above the horizon (and pixels outside the lens model)
    int onDem = 0;         //!< rays that meet the DEM
    int offDem = 0;        //!< rays towards the ground that leave the DEM without meeting it (or start below it)
    int onHoles = 0;       //!< rays that meet a hole too large to fill
    Eigen::Vector2d coveredCentrePx = Eigen::Vector2d::Constant( -1.0 );   //!< mean pixel (of the image, scan pixels for film) of the rays on the DEM
    Eigen::Vector2d uncoveredCentrePx = Eigen::Vector2d::Constant( -1.0 ); //!< mean pixel of the rays off the DEM or on holes
    std::string message;   //!< one sentence: covered, or how much is not and where

    //! Rays towards the ground.
    int groundSamples() const { return onDem + offDem + onHoles; }
    //! Share of the rays towards the ground that meet the DEM (0 when none points at the ground).
    double coveredFraction() const { return groundSamples() > 0 ? static_cast<double>( onDem ) / groundSamples() : 0.0; }
    bool complete() const { return groundSamples() > 0 && onDem == groundSamples(); }
  };

  /**
   * Samples the monoplotter's image on a grid of `options.columns` x
   * `options.rows` pixels (cell centres of the camera's frame; for a scanned
   * film, that frame mapped into the scan by its scan affine) and intersects
   * their rays with its DEM. Where the DEM covers at least half, the message says
   * where in the frame the rest lies; where less, where the covered part is
   * (a third of the frame each way: "the top left", "the right side" ...).
   */
  DemCoverageSummary demCoverageOfImage( const Monoplotter &monoplotter, const DemCoverageOptions &options = DemCoverageOptions() );

} // namespace geostation

#endif // GEOSTATION_DEM_DEMCOVERAGE_H
