// The final lines moved onto their band's centre (centrerefinement.h): a
// curved dark road between bright shoulders, drawn at sub-pixel positions,
// with a car on it and a shadow across it; the compiled polygon it starts
// from runs through pixel centres, a pixel or two off, with a kink round the
// car. Against the road's true centre line.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "extraction/centrerefinement.h"
#include "supersampledimage.h"

using namespace geostation;

namespace
{
  //! The true centre: a gentle arc across the image, y(x) in pixelInImage.
  double trueCentreY( double x ) { return 100.0 + 0.0008 * ( x - 150.0 ) * ( x - 150.0 ) + 0.3; }

  //! Distance of a point to the true centre line (dense sampling).
  double offTruth( const Eigen::Vector2d &p )
  {
    double best = 1e9;
    for ( double x = 0.0; x <= 300.0; x += 0.05 )
      best = std::min( best, ( p - Eigen::Vector2d( x, trueCentreY( x ) ) ).norm() );
    return best;
  }

  //! A 10 px dark road between 4 px bright shoulders on a textured field, noise 3 grey levels; a car and a shadow on it.
  //! A dark band of 6 px to `maxWidthPx`, 25 grey levels or more below its sides.
  LineObjectOptions darkRoad( double maxWidthPx )
  {
    LineObjectOptions object;
    object.polarity = -1;
    object.minContrast = 25.0;
    object.minWidthPx = 6.0;
    object.maxWidthPx = maxWidthPx;
    return object;
  }

  cv::Mat roadImage()
  {
    return supersampled( 5, []( double x, double y ) {
      const double across = std::abs( y - trueCentreY( x ) );
      double value = 110.0 + 10.0 * std::sin( x / 7.0 ) * std::cos( y / 5.0 ); // field
      if ( across < 5.0 )
        value = 60.0; // asphalt
      else if ( across < 9.0 )
        value = 170.0; // shoulders
      if ( x > 120.0 && x < 132.0 && y > trueCentreY( x ) - 5.0 && y < trueCentreY( x ) - 1.0 )
        value = 25.0; // a dark car in the upper lane
      if ( x > 200.0 && x < 214.0 && y < trueCentreY( x ) + 2.0 )
        value *= 0.45; // a tree's shadow over the upper shoulder and half the road
      return value;
    } );
  }
} // namespace

TEST( CentreRefinement, LinesMovedOntoTheBandCentre )
{
  const cv::Mat grey = roadImage();
  const LineObjectOptions object = darkRoad( 20.0 );
  // the compiled polygon: pixel centres 0.5-1.5 px off the centre, with a kink of 2 px more round the car
  CompiledPolygon compiled;
  for ( int x = 10; x <= 290; x += 10 )
  {
    const double kink = x >= 120 && x <= 130 ? 2.0 : 0.0;
    compiled.pixels.emplace_back( x + 0.5, std::floor( trueCentreY( x ) + 1.0 + kink ) + 0.5 );
  }
  compiled.endEnd = PolygonEnd::Intersection;
  double before = 0.0;
  for ( const Eigen::Vector2d &p : compiled.pixels )
    before = std::max( before, offTruth( p ) );

  const CentreRefinementSummary refined = refineLineCentres( GreyTiles( grey ), { compiled }, object );
  ASSERT_EQ( refined.lines.size(), 1u );
  const CompiledPolygon &line = refined.lines.front();
  EXPECT_EQ( line.endEnd, PolygonEnd::Intersection );
  EXPECT_EQ( line.startEnd, PolygonEnd::DeadEnd );
  // the end at the intersection stays where the branches meet
  EXPECT_LT( ( line.pixels.back() - compiled.pixels.back() ).norm(), 1e-9 );
  // everywhere else on the band's centre: the kink round the car is gone, the shadow pulls the line little
  // (measured 0.13 px on average, from 0.5-3.5 px)
  double worst = 0.0, sum = 0.0;
  int n = 0;
  const std::vector<Eigen::Vector2d> dense = [&] {
    std::vector<Eigen::Vector2d> d;
    for ( size_t i = 0; i + 1 < line.pixels.size(); ++i )
      for ( double t = 0.0; t < 1.0; t += 0.1 )
        d.push_back( line.pixels[i] + t * ( line.pixels[i + 1] - line.pixels[i] ) );
    return d;
  }();
  for ( const Eigen::Vector2d &p : dense )
  {
    if ( p.x() > 270.0 ) // the ramp into the intersection's end
      continue;
    const double d = offTruth( p );
    worst = std::max( worst, d );
    sum += d;
    ++n;
  }
  std::printf( "centre refinement: before up to %.2f px off, after %.3f px on average, worst %.3f px; %d of %d profiles found the band\n", before, sum / n, worst,
               refined.bandFound, refined.profiles );
  EXPECT_GT( before, 1.5 );
  EXPECT_LT( sum / n, 0.15 );
  EXPECT_LT( worst, 0.75 ); // measured 0.57, where the tree's shadow darkens half the road
  EXPECT_GT( refined.meanShiftPx, 0.8 );
}

TEST( CentreRefinement, NoBandLeavesTheLineAndBadOptionsThrow )
{
  // a flat field: nothing to move onto
  const cv::Mat field( 100, 100, CV_8U, cv::Scalar( 120 ) );
  CompiledPolygon line;
  line.pixels = { { 10.5, 50.5 }, { 90.5, 52.5 } };
  const CentreRefinementSummary same = refineLineCentres( GreyTiles( field ), { line }, LineObjectOptions() );
  ASSERT_EQ( same.lines.size(), 1u );
  EXPECT_EQ( same.bandFound, 0 );
  EXPECT_LT( ( same.lines.front().pixels.front() - line.pixels.front() ).norm(), 1e-9 );
  EXPECT_LT( ( same.lines.front().pixels.back() - line.pixels.back() ).norm(), 1e-9 );
  EXPECT_EQ( same.lines.front().pixels.size(), 2u );
  // a line too short to profile, and no line, come back as they were
  CompiledPolygon dot;
  dot.pixels = { { 50.5, 50.5 } };
  EXPECT_EQ( refineLineCentres( GreyTiles( field ), { dot }, LineObjectOptions() ).lines.front().pixels.size(), 1u );
  EXPECT_TRUE( refineLineCentres( GreyTiles( field ), {}, LineObjectOptions() ).lines.empty() );
  CentreRefinementOptions bad;
  bad.minSupport = 2 * bad.fitHalfWindow + 2;
  EXPECT_THROW( refineLineCentres( GreyTiles( field ), { line }, LineObjectOptions(), bad ), std::invalid_argument );
  bad = CentreRefinementOptions();
  bad.stepPx = 0.0;
  EXPECT_THROW( refineLineCentres( GreyTiles( field ), { line }, LineObjectOptions(), bad ), std::invalid_argument );
}

namespace
{
  //! A T junction: a 10 px dark road across (centre y = 100.3) and one up from it (centre x = 150.6), on a textured field.
  cv::Mat junctionImage()
  {
    return supersampled( 9, []( double x, double y ) {
      const bool across = std::abs( y - 100.3 ) < 5.0, up = std::abs( x - 150.6 ) < 5.0 && y < 100.3;
      return across || up ? 60.0 : 130.0 + 10.0 * std::sin( x / 6.0 ) * std::cos( y / 4.0 );
    } );
  }
} // namespace

TEST( CentreRefinement, BranchesMeetWhereTheirBandsCross )
{
  // three compiled polygons ending at the intersection's centre as the result matrix has it, 1.2 px right of and
  // 1.2 px below where the roads' centres cross, each a pixel off its band
  const Eigen::Vector2d truth( 150.6, 100.3 ), compiledCentre( 151.5, 101.5 );
  CompiledPolygon left, right, up;
  left.pixels = { { 10.5, 101.5 }, compiledCentre };
  left.endEnd = PolygonEnd::Intersection;
  right.pixels = { compiledCentre, { 290.5, 101.5 } };
  right.startEnd = PolygonEnd::Intersection;
  up.pixels = { { 151.5, 8.5 }, compiledCentre };
  up.endEnd = PolygonEnd::Intersection;
  const LineObjectOptions object = darkRoad( 16.0 );
  // and a stub too short to profile, from the intersection down
  CompiledPolygon stub;
  stub.pixels = { compiledCentre, compiledCentre + Eigen::Vector2d( 0.0, 3.0 ) };
  stub.startEnd = PolygonEnd::Intersection;
  const CentreRefinementSummary refined = refineLineCentres( GreyTiles( junctionImage() ), { left, right, up, stub }, object );
  ASSERT_EQ( refined.lines.size(), 4u );
  ASSERT_EQ( refined.junctions.size(), 1u );
  EXPECT_LT( ( refined.junctions.front().first - compiledCentre ).norm(), 1e-9 );
  EXPECT_LT( ( refined.movedIntersections( { compiledCentre } ).front() - refined.junctions.front().second ).norm(), 1e-9 );
  const Eigen::Vector2d a = refined.lines[0].pixels.back(), b = refined.lines[1].pixels.front(), c = refined.lines[2].pixels.back();
  std::printf( "junction: compiled %.2f px from the crossing of the centres, moved %.2f px\n", ( compiledCentre - truth ).norm(), ( a - truth ).norm() );
  // the branches still meet, now where the bands cross (measured 0.12 px; 1.50 px before)
  EXPECT_LT( ( a - b ).norm(), 1e-9 );
  EXPECT_LT( ( a - c ).norm(), 1e-9 );
  EXPECT_LT( ( a - refined.lines[3].pixels.front() ).norm(), 1e-9 ); // the stub's end goes with them
  EXPECT_LT( ( refined.lines[3].pixels.back() - stub.pixels.back() ).norm(), 1e-9 );
  EXPECT_LT( ( a - truth ).norm(), 0.3 );
  // and run on their centres up to it
  for ( const Eigen::Vector2d &p : refined.lines[0].pixels )
    EXPECT_LT( std::abs( p.y() - truth.y() ), 0.4 ) << p.transpose();
  for ( const Eigen::Vector2d &p : refined.lines[1].pixels )
    EXPECT_LT( std::abs( p.y() - truth.y() ), 0.4 ) << p.transpose();
  for ( const Eigen::Vector2d &p : refined.lines[2].pixels )
  {
    if ( p.y() > 12.0 ) // the road runs out of the image at the top: its last profiles are cut
    {
      EXPECT_LT( std::abs( p.x() - truth.x() ), 0.4 ) << p.transpose();
    }
  }
}
