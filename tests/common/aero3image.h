/***************************************************************************
  aero3image.h - a real aerial photograph (opencv-doc's aero3.jpg) and the
  truth digitised on it
  -------------------------------------------------------------------------
  An oblique view over a town by the sea, 640 x 480 px, roads 4 to 28 px
  wide among buildings, trees and fields. The centre lines of three main
  roads were digitised by hand on the photograph, each with a half-width
  generous enough to hold the road (they lie up to 6 px off the centres
  measured on profiles, aero3MeasuredRoads()); two areas certainly hold no
  road (the sea, the forest).
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_AERO3IMAGE_H
#define GEOSTATION_TESTS_AERO3IMAGE_H

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "imagelinescoring.h"

namespace geostation::aero3image
{
  //! Where Debian's opencv-doc puts OpenCV's sample images.
  inline std::string sampleImagePath( const std::string &file ) { return "/usr/share/doc/opencv-doc/examples/data/" + file; }

  //! Centre lines in pixelInImage of aero3.jpg.
  inline std::vector<TruthRoad> aero3MainRoads()
  {
    return { { "highway", 14.0, { { 345, 220 }, { 328, 260 }, { 306, 300 }, { 282, 340 }, { 267, 370 }, { 252, 400 }, { 237, 430 }, { 222, 460 }, { 213, 478 } } },
             { "road beside the highway", 5.0, { { 360, 250 }, { 350, 275 }, { 340, 300 }, { 320, 330 }, { 300, 362 }, { 285, 390 }, { 265, 417 }, { 242, 475 } } },
             { "cross road", 5.0, { { 405, 219.5 }, { 500, 219.5 }, { 560, 220 }, { 632, 220 } } } };
  }

  /**
   * Where the map-revision tests need the course to a pixel (they confirm
   * a mapped road within 2 m): the highway and the road beside it measured
   * on grey-level profiles across them every 10 rows (the band's edges at
   * the steepest gradients, a quadratic fitted through the centres, 0.4 and
   * 1.0 px RMS), over the stretches where both edges are clear. There the
   * hand-digitised lines above lie up to 6 px off the centre (the highway
   * is 16 px wide, not 28).
   */
  inline std::vector<TruthRoad> aero3MeasuredRoads()
  {
    return { { "highway", 8.0, { { 322.1, 265 }, { 306.6, 295 }, { 290.7, 325 }, { 274.7, 355 }, { 258.4, 385 }, { 241.8, 415 }, { 224.9, 445 }, { 207.8, 475 } } },
             { "road beside the highway", 4.0, { { 304.8, 355 }, { 289.5, 385 }, { 274.0, 415 }, { 258.1, 445 }, { 247.3, 465 } } },
             { "cross road", 3.0, { { 405, 219.5 }, { 500, 219.5 }, { 560, 220 }, { 632, 220 } } } };
  }

  //! Areas without roads on aero3.jpg: the sea above the coast, the forest in the lower left.
  inline std::vector<std::vector<cv::Point2f>> aero3RoadlessAreas()
  {
    return { { { 0, 0 }, { 640, 0 }, { 640, 8 }, { 0, 78 } },
             { { 0, 345 }, { 40, 332 }, { 120, 335 }, { 200, 360 }, { 235, 378 }, { 222, 400 }, { 200, 440 }, { 185, 480 }, { 0, 480 } } };
  }
} // namespace geostation::aero3image

#endif // GEOSTATION_TESTS_AERO3IMAGE_H
