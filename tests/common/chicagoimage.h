/***************************************************************************
  chicagoimage.h - a real 10 m image of a city and the truth digitised on it
  -------------------------------------------------------------------------
  SP27GTIF.TIF of Debian's r-cran-rgdal 1.6-4 (a GeoTIFF sample of
  remotesensing.org: central Chicago, 699 x 929 px, north up, 32.8 US ft
  = 10.0 m ground pixels), fetched into testdata/ by
  scripts/setup-debian.sh, and the oriented pair resampled from it
  (orthophotopair.h: the second photo 20 % of the footprint north).

  The truth, digitised by hand on the image at 3x with the help of mean
  profiles across each road (to about 1.5 px; the Kennedy expressway, two
  carriageways 10 px apart, to about 3 px): the centre lines of six main
  roads, each with its half width; and the lake beyond the shore, its
  breakwaters included, where no road runs.
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_CHICAGOIMAGE_H
#define GEOSTATION_TESTS_CHICAGOIMAGE_H

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "imagelinescoring.h"
#include "orthophotopair.h"

namespace geostation::chicagoimage
{
  //! Centre lines in pixelInImage of SP27GTIF.TIF.
  inline std::vector<TruthRoad> chicagoMainRoads()
  {
    return { { "Kennedy expressway", 6.0, { { 4, 14 }, { 27, 62 }, { 50, 110 }, { 62, 160 }, { 70, 195 }, { 95, 232 }, { 120, 268 }, { 145, 293 }, { 170, 315 }, { 187, 328 } } },
             { "Eisenhower expressway", 2.5, { { 2, 454.3 }, { 230, 453.4 } } },
             { "Roosevelt Road", 1.5, { { 2, 551.4 }, { 255, 548.9 } } },
             { "the street at row 307", 1.5, { { 2, 307.0 }, { 200, 306.5 } } },
             { "Michigan Avenue", 1.5, { { 354.5, 280 }, { 353.5, 500 }, { 354.5, 650 } } },
             { "Lake Shore Drive", 2.0, { { 344.8, 45 }, { 347.7, 72.4 }, { 350.2, 99.6 }, { 355.5, 124.5 }, { 357.7, 149.3 }, { 375.4, 166.6 }, { 397.3, 175.3 },
                                          { 408.8, 198.6 }, { 420.2, 221.9 }, { 430.1, 241.3 }, { 435.8, 262.1 }, { 438, 281 }, { 440, 300 }, { 441, 320 }, { 443, 340 } } } };
  }

  //! The lake north of Navy Pier (its breakwaters included) and east of the harbour, on SP27GTIF.TIF.
  inline std::vector<std::vector<cv::Point2f>> chicagoLake()
  {
    return { { { 400, 0 }, { 699, 0 }, { 699, 250 }, { 470, 250 }, { 450, 225 }, { 420, 190 }, { 380, 160 }, { 370, 140 }, { 368, 60 }, { 395, 35 } },
             { { 560, 300 }, { 699, 300 }, { 699, 740 }, { 610, 740 }, { 610, 560 }, { 560, 450 } } };
  }

  inline std::string chicagoImagePath() { return std::string( GEOSTATION_SOURCE_DIR ) + "/testdata/SP27GTIF.TIF"; }

  constexpr double kUsFootM = 1200.0 / 3937.0;
  constexpr double kGroundPixelM = 32.8 * kUsFootM;

  //! The pair over the image (after haveChicagoImage()).
  inline orthophotopair::OrthophotoPair chicagoPair()
  {
    return orthophotopair::orthophotoPair( cv::imread( chicagoImagePath(), cv::IMREAD_GRAYSCALE ), kGroundPixelM, 0.2 );
  }

  //! The image is fetched by scripts/setup-debian.sh; without it a local run skips, CI fails.
  inline bool haveChicagoImage()
  {
    if ( std::filesystem::exists( chicagoImagePath() ) )
      return true;
    const char *ci = std::getenv( "CI" );
    EXPECT_FALSE( ci && std::string( ci ) == "true" ) << chicagoImagePath() << " is missing: scripts/setup-debian.sh fetches it (Debian package r-cran-rgdal)";
    return false;
  }

} // namespace geostation::chicagoimage

#endif // GEOSTATION_TESTS_CHICAGOIMAGE_H
