/***************************************************************************
  testrealsatelliteextraction.cpp - road extraction with its defaults on a
  real 10 m panchromatic image of a city
  -------------------------------------------------------------------------
  The image: SP27GTIF.TIF of Debian's r-cran-rgdal 1.6-4 (a GeoTIFF sample
  of remotesensing.org: central Chicago, 699 x 929 px, north up, 32.8 US ft
  = 10.0 m ground pixels), fetched into testdata/ by
  scripts/setup-debian.sh. Streets are 1-3 px wide, expressways 3-10 px;
  the city's blocks, roofs and shadows beside them are as bright and as
  dark as the streets themselves.

  The pair: two vertical photos resampled from it over level ground
  (orthophotopair.h), so the pair is oriented and the ground pixel known,
  as a user's satellite stereo pair is.

  The truth, digitised by hand on the image at 3x with the help of mean
  profiles across each road (to about 1.5 px; the Kennedy expressway, two
  carriageways 10 px apart, to about 3 px): the centre lines of seven
  main roads, each with its half width; and the lake beyond the shore,
  its breakwaters included, where no line may lie.
 ***************************************************************************/
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "debugdrawing.h"
#include "extraction/roadnetworkextractor.h"
#include "imagelinescoring.h"
#include "matching/matchimage.h"
#include "orthophotopair.h"

using namespace geostation;
using namespace geostation::orthophotopair;

namespace
{
  struct TruthRoad
  {
    std::string name;
    double halfWidthPx;
    PixelPolyline centre; //!< pixelInImage of SP27GTIF.TIF
  };

  std::vector<TruthRoad> chicagoMainRoads()
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
  std::vector<std::vector<cv::Point2f>> chicagoLake()
  {
    return { { { 400, 0 }, { 699, 0 }, { 699, 250 }, { 470, 250 }, { 450, 225 }, { 420, 190 }, { 380, 160 }, { 370, 140 }, { 368, 60 }, { 395, 35 } },
             { { 560, 300 }, { 699, 300 }, { 699, 740 }, { 610, 740 }, { 610, 560 }, { 560, 450 } } };
  }

  std::string chicagoImagePath() { return std::string( GEOSTATION_SOURCE_DIR ) + "/testdata/SP27GTIF.TIF"; }

  constexpr double kUsFootM = 1200.0 / 3937.0;

  struct ChicagoResult
  {
    OrthophotoPair pair;
    RoadNetworkSummary summary;
    std::vector<PixelPolyline> lines; //!< in photo A
    std::vector<TruthRoad> truth;     //!< in photo A, where both photos see the ground
  };

  ChicagoResult extractChicago( const RoadNetworkOptions &options )
  {
    ChicagoResult r;
    const cv::Mat ortho = cv::imread( chicagoImagePath(), cv::IMREAD_GRAYSCALE );
    r.pair = orthophotoPair( ortho, 32.8 * kUsFootM, 0.2 );
    const OrientedImage a( r.pair.camera, r.pair.exterior[0] ), b( r.pair.camera, r.pair.exterior[1] );
    r.summary = extractRoadNetwork( MatchImage( r.pair.grey[0] ), MatchImage( r.pair.grey[1] ), &a, &b, options );
    for ( const CompiledPolygon &p : r.summary.extraction.linesA )
      r.lines.push_back( p.pixels );
    for ( const TruthRoad &road : chicagoMainRoads() )
      for ( const PixelPolyline &piece : inPhoto( r.pair, 0, { road.centre }, 10.0 ) )
        r.truth.push_back( { road.name, road.halfWidthPx, piece } );
    return r;
  }

  //! The length of `roads` within half-width + `tolerancePx` of `lines`, and their whole length.
  std::pair<double, double> foundOf( const std::vector<TruthRoad> &roads, const std::vector<PixelPolyline> &lines, double tolerancePx )
  {
    double total = 0.0, found = 0.0;
    for ( const TruthRoad &road : roads )
      alongLines( { road.centre }, [&]( const Eigen::Vector2d &p, double length ) {
        total += length;
        if ( distanceToLines( p, lines ) <= road.halfWidthPx + tolerancePx )
          found += length;
      } );
    return { found, total };
  }

  //! Length of `lines` (photo A) whose ground lies in the lake.
  double lengthInLake( const OrthophotoPair &pair, const std::vector<PixelPolyline> &lines )
  {
    const OrientedImage a( pair.camera, pair.exterior[0] );
    double inside = 0.0;
    alongLines( lines, [&]( const Eigen::Vector2d &p, double length ) {
      const std::optional<Ray> ray = a.worldRayFromPixel( p );
      const Eigen::Vector3d g = ray->origin + ( pair.groundM - ray->origin.z() ) / ray->direction.z() * ray->direction;
      const cv::Point2f inOrtho( static_cast<float>( g.x() / pair.gsdM + 0.5 * pair.ortho.width ), static_cast<float>( 0.5 * pair.ortho.height - g.y() / pair.gsdM ) );
      for ( const std::vector<cv::Point2f> &area : chicagoLake() )
        if ( cv::pointPolygonTest( area, inOrtho, false ) >= 0 )
          inside += length;
    } );
    return inside;
  }

  //! The image is fetched by scripts/setup-debian.sh; without it a local run skips, CI fails.
  bool haveChicagoImage()
  {
    if ( std::filesystem::exists( chicagoImagePath() ) )
      return true;
    const char *ci = std::getenv( "CI" );
    EXPECT_FALSE( ci && std::string( ci ) == "true" ) << chicagoImagePath() << " is missing: scripts/setup-debian.sh fetches it (Debian package r-cran-rgdal)";
    return false;
  }

  struct ChicagoScore
  {
    double found = 0.0;  //!< completeness on the main roads
    double lakePx = 0.0; //!< line in the lake
    double linePx = 0.0;
  };

  ChicagoScore scoreAndReport( const std::string &label, const ChicagoResult &r )
  {
    const auto [found, total] = foundOf( r.truth, r.lines, 2.0 );
    ChicagoScore score{ found / total, lengthInLake( r.pair, r.lines ), totalLength( r.lines ) };
    std::printf( "Chicago, %s: main roads %.2f found (%.0f of %.0f px); %.0f px of line, %.0f px in the lake; height %.1f m (truth 200), "
                 "widths %.1f-%.1f px, contrast %.0f (texture %.1f), %.1f s\n",
                 label.c_str(), score.found, found, total, score.linePx, score.lakePx, r.summary.meanHeightM, r.summary.widthsFromMetres->minPx,
                 r.summary.widthsFromMetres->maxPx, r.summary.minContrast, r.summary.textureGrey, r.summary.seconds );
    for ( const TruthRoad &road : chicagoMainRoads() )
    {
      std::vector<TruthRoad> pieces;
      for ( const TruthRoad &t : r.truth )
        if ( t.name == road.name )
          pieces.push_back( t );
      const auto [f, t] = foundOf( pieces, r.lines, 2.0 );
      std::printf( "  %s: %.2f found\n", road.name.c_str(), t > 0 ? f / t : 0.0 );
    }
    std::vector<PixelPolyline> truthLines;
    for ( const TruthRoad &t : r.truth )
      truthLines.push_back( t.centre );
    drawLinesForDebugging( "chicago_" + label.substr( 0, label.find( ' ' ) ), r.pair.grey[0], { { truthLines, cv::Scalar( 255, 0, 0 ) }, { r.lines, cv::Scalar( 0, 0, 255 ) } } );
    return score;
  }
} // namespace

// With the defaults, as a user would run it: either polarity, roads 3-30 m (1-3 px at 10 m), the contrast
// from the texture; then with MIN_CONTRAST 20 given. Aims: completeness >= 0.70 on the main roads, nothing
// in the lake. Both fail (disabled until they pass).
TEST( RealSatelliteImage, DISABLED_ChicagoMainRoadsWithTheDefaults )
{
  if ( !haveChicagoImage() )
    GTEST_SKIP() << "SP27GTIF.TIF not fetched (scripts/setup-debian.sh)";
  const ChicagoResult r = extractChicago( defaultRoadNetworkOptions() );
  const ChicagoScore defaults = scoreAndReport( "defaults", r );
  EXPECT_NEAR( r.summary.meanHeightM, 200.0, 2.0 );
  EXPECT_GE( defaults.found, 0.70 );
  EXPECT_LT( defaults.lakePx, 0.02 * defaults.linePx );

  RoadNetworkOptions given = defaultRoadNetworkOptions();
  given.contrastPerTexture = 0.0;
  given.coincident.extraction.object.minContrast = 20.0;
  const ChicagoScore contrast20 = scoreAndReport( "contrast 20 given", extractChicago( given ) );
  EXPECT_GE( contrast20.found, 0.70 );
  EXPECT_LT( contrast20.lakePx, 0.02 * contrast20.linePx );
}
