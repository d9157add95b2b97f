/***************************************************************************
  startingpoints.h - starting points on sample rows and columns (§4.1)
  -------------------------------------------------------------------------
  Rows and columns of a regular pattern are sample lines. Where a sample
  line's grey-level profile shows a band (candidates), the candidate is
  tested more closely: its direction (the orientation along which the
  band is brightest against both sides), and, on three profiles across
  that direction, the contrast, the width, the uniformity along the line
  and the straightness of the three centres. Candidates that pass are
  starting points for LEM.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_STARTINGPOINTS_H
#define GEOSTATION_EXTRACTION_STARTINGPOINTS_H

#include <vector>

#include <opencv2/core.hpp>

#include "extraction/crossprofile.h"
#include "extraction/linestate.h"

namespace geostation
{

  struct StartingPointOptions
  {
    int sampleSpacingPx = 48;    //!< between sample rows, and between sample columns
    double probeLengthPx = 0.0;  //!< 0: 3 x the band's width, at least 24 px (the straightness test's length)
    int directions = 36;         //!< orientations tried (180 degrees / this apart)
    double straightnessPx = 1.5; //!< the middle centre off the line through the outer two, at most
    double widthChange = 0.35;   //!< the three widths within this fraction of their mean

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct StartingPointSummary
  {
    std::vector<LineState> points; //!< strongest first; direction is one of the two along the line
    int candidates = 0;            //!< band candidates on the sample lines
  };

  /**
   * Starting points in the window `area` of the image (sample lines inside
   * it; tests may look a little beyond).
   */
  StartingPointSummary findStartingPoints( const cv::Mat &grey, const cv::Rect &area, const LineObjectOptions &object, const StartingPointOptions &options );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_STARTINGPOINTS_H
