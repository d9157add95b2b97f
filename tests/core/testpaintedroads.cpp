/***************************************************************************
  testpaintedroads.cpp - road extraction with its defaults on road scenes
  painted independently of the survey simulator (paintedroads.h)
  -------------------------------------------------------------------------
  One camera model for both photos; fields brighter and darker than the
  roads; a main road with a dashed centre marking and edge lines; trees
  over a dark road; ground pixels of 0.15, 0.5, 2 and 10 m, so that the
  same roads are 40-73 px, 12-22 px, 4-7 px and (wider roads) 1-3 px wide.
  Scored by the buffer method in the first photo (buffer: the narrowest
  road's width, at least 2 px), within the part both photos see. The aims
  (issue "extraction that generalises"): completeness >= 0.85 and
  correctness >= 0.90 in every scene. A scene that misses them stays here,
  disabled, until it meets them.
 ***************************************************************************/
#include <algorithm>
#include <cstdio>
#include <tuple>

#include <gtest/gtest.h>

#include "debugdrawing.h"
#include "extraction/companionlines.h"
#include "extraction/roadnetworkextractor.h"
#include "imagelinescoring.h"
#include "matching/matchimage.h"
#include "paintedroads.h"

using namespace geostation;
using namespace geostation::paintedroads;

namespace
{
  struct SceneResult
  {
    ImageBufferScore score;
    RoadNetworkSummary summary;
  };

  SceneResult extractWithDefaults( const RoadScene &scene )
  {
    const PaintedRoadPair pair = paintedRoadPair( scene );
    const OrientedImage a( pair.camera, pair.exterior[0] ), b( pair.camera, pair.exterior[1] );
    const MatchImage imageA( pair.grey[0] ), imageB( pair.grey[1] );
    SceneResult r;
    r.summary = extractRoadNetwork( imageA, imageB, &a, &b, defaultRoadNetworkOptions() ); // no height, widths or polarity given
    std::vector<PixelPolyline> lines;
    for ( const CompiledPolygon &p : r.summary.extraction.linesA )
      lines.push_back( p.pixels );
    const double narrowestPx = *std::min_element( scene.widthsM.begin(), scene.widthsM.end() ) / scene.gsdM;
    r.score = imageBufferScore( lines, truthInPhoto( pair, 0, 10.0 ), std::max( 2.0, narrowestPx ) );
    const double quality = r.score.completeness * r.score.correctness / ( r.score.completeness + r.score.correctness - r.score.completeness * r.score.correctness );
    std::printf( "%s: completeness %.2f, correctness %.2f, quality %.2f, RMS %.2f px; height %.1f m (truth 300), widths %.1f-%.1f px, contrast %.0f, %.1f s\n",
                 scene.name.c_str(), r.score.completeness, r.score.correctness, quality, r.score.rmsPx, r.summary.meanHeightM, r.summary.widthsFromMetres->minPx,
                 r.summary.widthsFromMetres->maxPx, r.summary.minContrast, r.summary.seconds );
    drawLinesForDebugging( "painted_" + scene.name.substr( 0, scene.name.find( ' ', 4 ) ), pair.grey[0],
                           { { truthInPhoto( pair, 0, 10.0 ), cv::Scalar( 0, 255, 0 ) }, { lines, cv::Scalar( 0, 0, 255 ) } } );
    return r;
  }

  void expectAims( const RoadScene &scene )
  {
    const SceneResult r = extractWithDefaults( scene );
    ASSERT_TRUE( r.summary.terrainEstimate ) << "the height is estimated from the pair";
    EXPECT_NEAR( r.summary.meanHeightM, 300.0, 0.01 * scene.width * scene.gsdM ); // within 1 % of the flying height
    EXPECT_GE( r.score.completeness, 0.85 );
    EXPECT_GE( r.score.correctness, 0.90 );
  }

  const RoadScene &scene( const std::string &prefix )
  {
    static const std::vector<RoadScene> all = scenes();
    return *std::find_if( all.begin(), all.end(), [&]( const RoadScene &s ) { return s.name.rfind( prefix, 0 ) == 0; } );
  }
} // namespace

TEST( PaintedRoads, AerialHalfMetrePixels ) { expectAims( scene( "aerial" ) ); }

TEST( PaintedRoads, RegionalTwoMetrePixels ) { expectAims( scene( "regional" ) ); }

TEST( PaintedRoads, SatelliteTenMetrePixelsRoadsOneToThreePixelsWide ) { expectAims( scene( "satellite" ) ); }

// Known failing: completeness 0.66 (correctness 1.00). At 40-73 px the main road, where it crosses fields
// of its own grey, is told from them only by its edge lines (1 px), which lie inside the band; the dark
// road is not found: its row of trees, darker still, joins it into one dark band 70-80 px wide whose edge
// on the trees' side follows the crowns, so no starting point passes as a straight band of steady width.
TEST( PaintedRoads, DISABLED_LowAerialRoadsFortyToSeventyPixelsWide ) { expectAims( scene( "low aerial" ) ); }

TEST( PaintedRoads, WidthsInMetresBecomePixelsByTheGroundPixel )
{
  const PaintedRoadPair pair = paintedRoadPair( { "small", 2.0, { 14.0, 10.0, 8.0 }, 200 } );
  const OrientedImage a( pair.camera, pair.exterior[0] );
  const RoadWidthsPx w = widthsPxFor( a, 300.0, { 3.0, 30.0 } );
  EXPECT_NEAR( w.groundPixelM, 2.0, 0.01 );
  EXPECT_NEAR( w.minPx, 1.5, 0.01 );
  EXPECT_NEAR( w.maxPx, 15.0, 0.1 );
  EXPECT_FALSE( w.clamped );
  const RoadWidthsPx fine = widthsPxFor( a, 300.0, { 1.0, 400.0 } );
  EXPECT_DOUBLE_EQ( fine.minPx, 1.0 );
  EXPECT_DOUBLE_EQ( fine.maxPx, kMaxRoadWidthPx );
  EXPECT_TRUE( fine.clamped );
  EXPECT_THROW( widthsPxFor( a, 300.0, { 5.0, 3.0 } ), std::invalid_argument );
  EXPECT_THROW( widthsPxFor( a, 300.0, { 0.0, 3.0 } ), std::invalid_argument );
  EXPECT_THROW( widthsPxFor( a, 300.0 + 200.0 * 2.0 + 10.0, { 3.0, 30.0 } ), std::invalid_argument ) << "the ground above the camera";
}

namespace
{
  //! A horizontal band of `grey` from row `top` to `top + height` (exclusive) across the image.
  void paintBand( cv::Mat &image, int top, int height, int grey ) { image.rowRange( top, top + height ).setTo( grey ); }

  CompiledPolygon horizontalLine( double row, double from, double to )
  {
    CompiledPolygon line;
    line.pixels = { { from, row }, { to, row } };
    line.symbols = "I";
    return line;
  }

  //! Bands (top row, height, grey) on a ground of `ground` grey, 300 x 200 px, and the lines kept of `lines` (widths `narrowestPx` to 30 px).
  CompanionLineSummary keptOf( int ground, const std::vector<std::tuple<int, int, int>> &bands, const std::vector<CompiledPolygon> &lines, double narrowestPx = 2.0 )
  {
    cv::Mat image( 200, 300, CV_8U, cv::Scalar( ground ) );
    for ( const auto &[top, height, grey] : bands )
      paintBand( image, top, height, grey );
    LineObjectOptions object;
    object.minWidthPx = narrowestPx;
    object.maxWidthPx = 30.0;
    return removeCompanionLines( GreyTiles( image ), lines, object );
  }
}

TEST( CompanionLines, ShouldersBesideARoadAreNotRoads )
{
  // grass 90, bright shoulders (3 px, 200) either side of dark asphalt (14 px, 60)
  const CompanionLineSummary kept = keptOf( 90, { { 90, 3, 200 }, { 93, 14, 60 }, { 107, 3, 200 } },
                                            { horizontalLine( 100.0, 20.0, 280.0 ), horizontalLine( 91.5, 30.0, 270.0 ), horizontalLine( 108.5, 40.0, 200.0 ) } );
  EXPECT_EQ( kept.removed, 2 );
  ASSERT_EQ( kept.lines.size(), 1u );
  EXPECT_DOUBLE_EQ( kept.lines[0].pixels[0].y(), 100.0 );
  EXPECT_NEAR( kept.widthsPx[0], 14.0, 1.5 );
}

TEST( CompanionLines, TwoCarriagewaysOfOneWidthAndARoadFarAwayStay )
{
  // two carriageways (12 px, 60) with a 4 px verge between them, and a narrow road (4 px) far away
  const std::vector<CompiledPolygon> lines = { horizontalLine( 66.0, 20.0, 280.0 ), horizontalLine( 82.0, 20.0, 280.0 ), horizontalLine( 152.0, 20.0, 280.0 ) };
  const CompanionLineSummary kept = keptOf( 150, { { 60, 12, 60 }, { 76, 12, 60 }, { 150, 4, 60 } }, lines );
  EXPECT_EQ( kept.removed, 0 );
  EXPECT_EQ( kept.lines.size(), 3u );
  const cv::Mat image( 20, 20, CV_8U, cv::Scalar( 0 ) );
  EXPECT_THROW( removeCompanionLines( GreyTiles( image ), lines, LineObjectOptions(), CompanionLineOptions { 0.0, 0.8, 2.0 } ), std::invalid_argument );
}

TEST( CompanionLines, AShoulderAlongARoadFoundInPiecesIsNoRoad )
{
  // the road found in three pieces (a tree's shadow, a junction between them), its shoulder as one line along all
  // three: beside no single piece for most of its length, beside the road everywhere
  const CompanionLineSummary kept = keptOf( 90, { { 90, 3, 200 }, { 93, 14, 60 }, { 107, 3, 200 } },
                                            { horizontalLine( 100.0, 20.0, 100.0 ), horizontalLine( 100.0, 110.0, 190.0 ), horizontalLine( 100.0, 200.0, 280.0 ),
                                              horizontalLine( 108.5, 25.0, 275.0 ) } );
  EXPECT_EQ( kept.removed, 1 );
  ASSERT_EQ( kept.lines.size(), 3u );
  for ( const CompiledPolygon &line : kept.lines )
    EXPECT_DOUBLE_EQ( line.pixels[0].y(), 100.0 );
}

TEST( CompanionLines, AShoulderAndItsRoadCompiledAsOneLineLoseTheShoulder )
{
  // one line along a shoulder (4 px) from the right to column 40, where a junction took it onto the road (14 px),
  // and back along the road: the shoulder's stretch, narrower than the narrowest road looked for (6 px), goes
  CompiledPolygon line;
  line.pixels = { { 280.0, 109.0 }, { 40.0, 109.0 }, { 40.0, 100.0 }, { 280.0, 100.0 } };
  line.symbols = "I";
  const std::vector<std::tuple<int, int, int>> road = { { 89, 4, 200 }, { 93, 14, 60 }, { 107, 4, 200 } };
  const CompanionLineSummary kept = keptOf( 90, road, { line }, 6.0 );
  EXPECT_EQ( kept.removed, 0 );
  EXPECT_EQ( kept.cut, 1 );
  double onShoulder = 0.0, onRoad = 0.0;
  for ( const CompiledPolygon &piece : kept.lines )
    for ( size_t i = 0; i + 1 < piece.pixels.size(); ++i )
    {
      const Eigen::Vector2d a = piece.pixels[i], b = piece.pixels[i + 1];
      if ( std::abs( a.y() - 109.0 ) < 1.5 && std::abs( b.y() - 109.0 ) < 1.5 )
        onShoulder += ( b - a ).norm();
      if ( std::abs( a.y() - 100.0 ) < 1.5 && std::abs( b.y() - 100.0 ) < 1.5 )
        onRoad += ( b - a ).norm();
    }
  EXPECT_LT( onShoulder, 2.0 * 14.0 ) << "next to the junction, where the line has not come back beside itself, at most";
  EXPECT_GT( onRoad, 200.0 );
  // the same line with roads looked for from 2 px: the shoulder could be a road, and stays
  EXPECT_EQ( keptOf( 90, road, { line } ).cut, 0 );
}
