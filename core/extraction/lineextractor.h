/***************************************************************************
  lineextractor.h - line extraction in one image (report §3, §4.1)
  -------------------------------------------------------------------------
  The iterative application of starting-point search, LEM and REM: each
  starting point not on a known line is followed in both directions, LEM
  and REM handing over to each other, and the result is drawn into the
  result matrix (S, *, +) as it is found, so later lines stop where they
  meet it. Starting points are searched sub-image by sub-image in raster
  order (the report's 1024 x 1024 mosaic); lines are followed across
  sub-image borders directly, since the image is held whole.

  A continuation run starts from given dead ends (the verification dead
  ends of the coincident procedure) and may skip the starting points.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_LINEEXTRACTOR_H
#define GEOSTATION_EXTRACTION_LINEEXTRACTOR_H

#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "extraction/localextraction.h"
#include "extraction/regionalextraction.h"
#include "extraction/resultmatrix.h"
#include "extraction/startingpoints.h"

namespace geostation
{

  struct LineExtractionOptions
  {
    LineObjectOptions object;
    StartingPointOptions start;
    LemOptions lem;
    RemOptions rem;
    int subImageSizePx = 1024;
    int minSteps = 3;      //!< a starting point is kept only when LEM makes this many steps from it (both directions together)
    int maxHandovers = 40; //!< LEM / REM alternations on one line

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  //! Time and pixels of line per stage (the benchmark's pixels per second).
  struct StageCounts
  {
    double seconds = 0.0;
    double linePx = 0.0; //!< length of line produced
    long imagePixels = 0; //!< pixels of image searched (starting points)
  };

  struct LineExtractionSummary
  {
    int startingPoints = 0;  //!< found
    int linesStarted = 0;    //!< starting points followed (not on a known line, enough steps)
    int startsRejected = 0;  //!< fewer than minSteps
    int continued = 0;       //!< dead ends continued
    std::vector<DeadEnd> deadEnds; //!< where the lines stopped (final kinds; both ends of a line)
    StageCounts startStage, lemStage, remStage;
    double linePx = 0.0;     //!< total length drawn
    bool cancelled = false;
  };

  //! Fraction done; return false to cancel.
  using ExtractionProgress = std::function<bool( double fraction )>;

  /**
   * Extracts lines into `matrix` (same size as `grey`, CV_8UC1). Throws
   * std::invalid_argument for a bad image or options.
   */
  LineExtractionSummary extractLines( const cv::Mat &grey, ResultMatrix &matrix, const std::vector<DeadEnd> &continueFrom, bool searchStartingPoints,
                                      const LineExtractionOptions &options, const ExtractionProgress &progress = nullptr );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_LINEEXTRACTOR_H
