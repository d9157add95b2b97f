// A line along a road's border goes onto the road (roadborders.h): a dark
// road 12 px wide between bright borders 4 px wide on a textured field, the
// bands' edges at sub-pixel positions, and a line along one border. Against
// the road's true centre line; and what must not move: a line on the road, a
// narrow band beside a wide dark strip with no border beyond it.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "extraction/roadborders.h"
#include "supersampledimage.h"

using namespace geostation;

namespace
{
  //! The road's true centre: a straight line across the image, y(x) in pixelInImage.
  double centreY( double x ) { return 100.3 + 0.08 * ( x - 150.0 ); }
  //! Across the road from its centre (px, positive below), perpendicular to it.
  double across( double x, double y ) { return ( y - centreY( x ) ) / std::sqrt( 1.0 + 0.08 * 0.08 ); }

  double field( double x, double y ) { return 115.0 + 8.0 * std::sin( x / 7.0 ) * std::cos( y / 5.0 ); }

  //! Asphalt (60) 12 px wide between bright borders (175) 4 px wide.
  cv::Mat borderedRoad()
  {
    return supersampled( 11, []( double x, double y ) {
      const double a = std::abs( across( x, y ) );
      return a < 6.0 ? 60.0 : a < 10.0 ? 175.0 : field( x, y );
    } );
  }

  //! Either polarity, roads 6-30 px, 15 grey levels: as the defaults at half a metre.
  LineObjectOptions eitherPolarity()
  {
    LineObjectOptions object;
    object.polarity = 0;
    object.minContrast = 15.0;
    object.minWidthPx = 6.0;
    object.maxWidthPx = 30.0;
    return object;
  }

  //! A line from x = `from` to `to` (20 to 280) at `offset` px across the road from its centre.
  CompiledPolygon lineAt( double offset, int from = 20, int to = 280 )
  {
    CompiledPolygon line;
    const double norm = std::sqrt( 1.0 + 0.08 * 0.08 );
    for ( int x = from; x <= to; x += 20 )
      line.pixels.emplace_back( x - offset * 0.08 / norm, centreY( x ) + offset / norm );
    return line;
  }

  //! The mean and largest distance of a line (densified) from the road's centre, leaving out `skipPx` at its start.
  std::pair<double, double> offCentre( const CompiledPolygon &line, double skipPx = 0.0 )
  {
    double sum = 0.0, worst = 0.0, along = 0.0;
    int n = 0;
    for ( size_t i = 0; i + 1 < line.pixels.size(); ++i )
      for ( double t = 0.0; t < 1.0; t += 0.1 )
      {
        const Eigen::Vector2d p = line.pixels[i] + t * ( line.pixels[i + 1] - line.pixels[i] );
        along += 0.1 * ( line.pixels[i + 1] - line.pixels[i] ).norm();
        if ( along < skipPx )
          continue;
        const double d = std::abs( across( p.x(), p.y() ) );
        sum += d;
        worst = std::max( worst, d );
        ++n;
      }
    return { sum / std::max( 1, n ), worst };
  }
} // namespace

TEST( RoadBorders, ALineOnABorderGoesOntoTheRoad )
{
  const cv::Mat grey = borderedRoad();
  for ( const double side : { -8.0, 8.0, -6.5 } ) // on either border, and on the seam between a border and the asphalt
  {
    const RoadBorderSummary s = moveBordersOntoRoads( GreyTiles( grey ), { lineAt( side ) }, eitherPolarity() );
    ASSERT_EQ( s.lines.size(), 1u ) << side;
    EXPECT_EQ( s.moved, 1 ) << side;
    const auto [mean, worst] = offCentre( s.lines.front() );
    std::printf( "a line %.1f px off the road's centre, moved: %.2f px on average, at most %.2f px\n", side, mean, worst );
    EXPECT_LT( mean, 0.6 ) << side;
    EXPECT_LT( worst, 1.5 ) << side;
  }
}

TEST( RoadBorders, TheJunctionEndHoldsAndTheRoadFoundTwiceGoes )
{
  const cv::Mat grey = borderedRoad();
  CompiledPolygon border = lineAt( -8.0 );
  border.startEnd = PolygonEnd::Intersection;
  const RoadBorderSummary alone = moveBordersOntoRoads( GreyTiles( grey ), { border }, eitherPolarity() );
  ASSERT_EQ( alone.lines.size(), 1u );
  EXPECT_EQ( alone.lines.front().startEnd, PolygonEnd::Intersection );
  EXPECT_LT( ( alone.lines.front().pixels.front() - border.pixels.front() ).norm(), 1e-9 ); // still where its junction is
  EXPECT_LT( offCentre( alone.lines.front(), 20.0 ).first, 0.6 );                        // and on the road past the ramp

  // the road had a line of its own: the border's goes, the road's stays as it was
  const CompiledPolygon road = lineAt( 0.0 );
  const RoadBorderSummary both = moveBordersOntoRoads( GreyTiles( grey ), { road, lineAt( 8.0 ) }, eitherPolarity() );
  ASSERT_EQ( both.lines.size(), 1u );
  EXPECT_EQ( both.duplicates, 1 );
  EXPECT_EQ( both.lines.front().pixels, road.pixels );
}

TEST( RoadBorders, TheStretchesOnTheRoadsOwnLinesGo )
{
  // the road found in two lines (x 20-100 and 200-280) with a gap between, and its border followed all along: moved,
  // the border's line keeps the gap's stretch only, on the road, its ends where the road's lines end
  const cv::Mat grey = borderedRoad();
  const CompiledPolygon west = lineAt( 0.0, 20, 100 ), east = lineAt( 0.0, 200, 280 );
  const RoadBorderSummary s = moveBordersOntoRoads( GreyTiles( grey ), { west, east, lineAt( 8.0 ) }, eitherPolarity() );
  EXPECT_EQ( s.moved, 1 );
  EXPECT_EQ( s.repeatsCut, 1 );
  ASSERT_EQ( s.lines.size(), 3u );
  EXPECT_EQ( s.lines[0].pixels, west.pixels );
  EXPECT_EQ( s.lines[1].pixels, east.pixels );
  const CompiledPolygon &gap = s.lines[2];
  const double first = std::min( gap.pixels.front().x(), gap.pixels.back().x() ), last = std::max( gap.pixels.front().x(), gap.pixels.back().x() );
  std::printf( "the gap's stretch: x %.1f to %.1f, %.2f px off the centre on average\n", first, last, offCentre( gap ).first );
  EXPECT_NEAR( first, 100.0, 8.0 );
  EXPECT_NEAR( last, 200.0, 8.0 );
  EXPECT_LT( offCentre( gap ).first, 0.6 );
  EXPECT_EQ( gap.startEnd, PolygonEnd::DeadEnd );
  EXPECT_EQ( gap.endEnd, PolygonEnd::DeadEnd );
}

TEST( RoadBorders, WhatIsNoBorderStays )
{
  // a line on the road itself
  const cv::Mat grey = borderedRoad();
  const RoadBorderSummary onRoad = moveBordersOntoRoads( GreyTiles( grey ), { lineAt( 0.3 ) }, eitherPolarity() );
  EXPECT_EQ( onRoad.moved, 0 );
  EXPECT_EQ( onRoad.lines.front().pixels, lineAt( 0.3 ).pixels );

  // a bright strip 4 px wide beside a dark strip of field 14 px wide, with only the field beyond: no road between borders
  const cv::Mat strip = supersampled( 12, []( double x, double y ) {
    const double a = across( x, y );
    return a > -4.0 && a < 0.0 ? 175.0 : a >= 0.0 && a < 14.0 ? 60.0 : field( x, y );
  } );
  const RoadBorderSummary beside = moveBordersOntoRoads( GreyTiles( strip ), { lineAt( -2.0 ) }, eitherPolarity() );
  EXPECT_EQ( beside.moved, 0 );

  // two dark roads side by side (a dual carriageway, a bright median between): the line on one stays on it
  const cv::Mat dual = supersampled( 13, []( double x, double y ) {
    const double a = across( x, y );
    return ( a > -16.0 && a < -4.0 ) || ( a > 4.0 && a < 16.0 ) ? 60.0 : std::abs( a ) <= 4.0 || std::abs( a ) < 20.0 ? 175.0 : field( x, y );
  } );
  const RoadBorderSummary carriageway = moveBordersOntoRoads( GreyTiles( dual ), { lineAt( -10.0 ) }, eitherPolarity() );
  EXPECT_EQ( carriageway.moved, 0 );
}

TEST( RoadBorders, BadOptionsThrow )
{
  const cv::Mat grey = borderedRoad();
  RoadBorderOptions options;
  options.minShare = 0.0;
  EXPECT_THROW( moveBordersOntoRoads( GreyTiles( grey ), {}, eitherPolarity(), options ), std::invalid_argument );
  options = RoadBorderOptions();
  options.roadOverBorder = 0.5;
  EXPECT_THROW( options.check(), std::invalid_argument );
  // no lines, nothing to do
  EXPECT_TRUE( moveBordersOntoRoads( GreyTiles( grey ), {}, eitherPolarity() ).lines.empty() );
}
