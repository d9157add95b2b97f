/***************************************************************************
  terrainheight.h - the mean terrain height of an oriented pair, by matching
  -------------------------------------------------------------------------
  Road extraction maps one image into the other through the terrain; with
  neither a DEM nor a mean height given, the height comes from the pair.
  A 9 x 9 grid of points of A is searched along its whole epipolar curve in
  B (depths 1 m to 100 km), which on fields sown in rows, tree rows or any
  texture that repeats finds the right place and its aliases with the same
  correlation. So the search is done in two steps:

    1. votes: every separate correlation peak of every grid point, turned
       into a height; the terrain is the height band (2 % of the flying
       height above it, at least 4 pixels of parallax) that most grid
       points share - an alias lands at another height for each point; a
       texture that repeats the same way everywhere (its aliases shared by
       nearly as many points) is said to, and no height is claimed;
    2. each grid point is matched again by least squares only where its
       curve crosses that band, a match kept only where no second peak in
       the band comes close; the estimate is their median with its spread.

  Expected failures (no overlap, no texture, no band shared by 5 points)
  come back as a status other than Estimated, with a sentence saying what
  was tried.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_TERRAINHEIGHT_H
#define GEOSTATION_EXTRACTION_TERRAINHEIGHT_H

#include <string>

#include "extraction/pairmatchwindows.h"
#include "geometry/projection.h"

namespace geostation
{

  struct TerrainHeightEstimate
  {
    enum class Status
    {
      Estimated,
      Unreadable,       //!< the images cannot be read for matching
      NoSharedHeight,   //!< no height shared by enough grid points (no overlap, too little texture)
      RepeatingTexture, //!< two heights shared nearly as widely: the texture's aliases
      NoUniqueMatch,    //!< a height shared, but too few points match there without a second peak
    };
    Status status = Status::Estimated;
    std::string message; //!< one sentence, what was tried, when not Estimated
    double heightM = 0.0;
    int points = 0;       //!< grid points matched by least squares within the band the median is taken from
    double spreadM = 0.0; //!< median absolute deviation of their heights
    int votingPoints = 0; //!< grid points whose correlation peaks voted for the band
    bool byLeastSquares = true; //!< the points matched by least squares (else their correlation peaks in the band)

    bool ok() const { return status == Status::Estimated; }
  };

  //! The mean terrain height of the pair (A, B) from a 9 x 9 grid of A, or the status saying why it cannot be told.
  TerrainHeightEstimate estimateTerrainHeight( const OrientedImage &a, const OrientedImage &b, PairMatchWindows &images );
  //! The same over two whole images.
  TerrainHeightEstimate estimateTerrainHeight( const OrientedImage &a, const OrientedImage &b, const MatchImage &imageA, const MatchImage &imageB );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_TERRAINHEIGHT_H
