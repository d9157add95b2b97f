/***************************************************************************
  lineextractor.h - line extraction in one image (report §3, §4.1)
  -------------------------------------------------------------------------
  The iterative application of starting-point search, LEM and REM: each
  starting point not on a known line is followed in both directions, LEM
  and REM handing over to each other, and the result is drawn into the
  result matrix (S, *, +) as it is found, so later lines stop where they
  meet it.

  The image is processed by sub-images (Kazmierczak et al.'s (1983) mosaic of 1024 x 1024
  pixels, overlapping): each is read as a window, starting points are
  searched in it, and LEM and REM follow lines within it. A line reaching
  the window's edge leaves a temporary dead end there, continued when the
  adjacent sub-image is processed: first in raster order, then in further
  runs through the sub-images that have temporary dead ends left (lines
  pointing back into sub-images already processed), without starting
  points, until none are left. Only the result matrix is held whole (one
  byte per pixel); the image is read a window at a time (greytiles.h).

  A continuation run starts from given dead ends (the verification dead
  ends of the coincident procedure) and may skip the starting points.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_LINEEXTRACTOR_H
#define GEOSTATION_EXTRACTION_LINEEXTRACTOR_H

#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "progress/progress.h"
#include "extraction/greytiles.h"
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
    int subImageOverlapPx = 0; //!< each side of a sub-image's window; 0: 3 x the widest road + 16, at least 32 (a line stops within that of the window's edge)
    int maxSubImageRuns = 6;   //!< runs through the sub-images; temporary dead ends left after the last become final
    int minSteps = 3;      //!< a starting point is kept only when LEM makes this many steps from it (both directions together)
    int maxHandovers = 40; //!< LEM / REM alternations on one line

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
    //! The overlap in use (subImageOverlapPx, or its automatic value).
    int overlapPx() const;
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
    int subImages = 0;       //!< sub-images processed (counted once per run)
    int subImageRuns = 0;    //!< runs through the sub-images
    int temporaryDeadEnds = 0; //!< lines continued across a sub-image border
    std::vector<DeadEnd> deadEnds; //!< where the lines stopped (final kinds; both ends of a line)
    StageCounts startStage, lemStage, remStage;
    double linePx = 0.0;     //!< total length drawn
    bool cancelled = false;
  };

  //! Fraction done; return false to cancel.

  /**
   * Extracts lines into `matrix` (the image's size) from the image `grey`
   * is read through; `continueFrom` and the summary are in image pixels.
   * Throws std::invalid_argument for bad options or a matrix of another
   * size; reader errors propagate.
   */
  LineExtractionSummary extractLines( const GreyTiles &grey, ResultMatrix &matrix, const std::vector<DeadEnd> &continueFrom, bool searchStartingPoints,
                                      const LineExtractionOptions &options, const Progress &progress = Progress() );

  //! The same for an image held in memory (CV_8UC1).
  LineExtractionSummary extractLines( const cv::Mat &grey, ResultMatrix &matrix, const std::vector<DeadEnd> &continueFrom, bool searchStartingPoints,
                                      const LineExtractionOptions &options, const Progress &progress = Progress() );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_LINEEXTRACTOR_H
