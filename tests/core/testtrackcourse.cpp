/***************************************************************************
  testtrackcourse.cpp - a road line keeps its course beside the van's track
  -------------------------------------------------------------------------
  The guards that keep a traced line on its own road line: track
  coordinates on a curved trajectory, the line's direction turned with
  the track beyond its last chord, the corridor that cuts a follower's
  jump across the road, the recent offset that a stray last vertex does
  not move, the lateral check of a station's vertices as they join the
  run's line (beyond a gap too, and a station whose first vertices
  strayed), and the seed that picks a worn stripe, not its side, or a
  stripe beyond a long crack at the click.
 ***************************************************************************/
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tracing/lineprofile.h"
#include "tracing/runline.h"
#include "tracing/trackgeometry.h"

using namespace geostation;

namespace
{
  constexpr double kRadius = 220.0; // the highway preset's curve

  //! Camera centres every 10 m on a 220 m radius left-hand curve, 2.6 m above the road.
  std::vector<Eigen::Vector3d> curvedTrack( int stations = 20 )
  {
    std::vector<Eigen::Vector3d> track;
    for ( int i = 0; i < stations; ++i )
    {
      const double a = i * 10.0 / kRadius;
      track.emplace_back( kRadius * std::sin( a ), kRadius * ( 1.0 - std::cos( a ) ), 102.6 );
    }
    return track;
  }

  //! A point `leftM` to the left of the curve's centre line, `arcM` along it, on the road.
  Eigen::Vector3d beside( double arcM, double leftM )
  {
    const double a = arcM / kRadius, r = kRadius - leftM;
    return { r * std::sin( a ), kRadius - r * std::cos( a ), 100.0 };
  }

  //! A station's vertex `leftM` to the left of the curve's centre line, `arcM` along it, with σ (m).
  LineVertex3d vertexBeside( double arcM, double leftM, double sigmaPlanM, double sigmaHeightM )
  {
    LineVertex3d v;
    v.point = beside( arcM, leftM );
    v.sigmaM = Eigen::Vector3d( sigmaPlanM, sigmaPlanM, sigmaHeightM );
    v.covariance = v.sigmaM.cwiseAbs2().asDiagonal();
    return v;
  }

  //! Station `id`'s part of a run along `track`.
  StationPart stationPartOn( const std::vector<Eigen::Vector3d> &track, const std::string &id )
  {
    StationPart part;
    part.stationId = id;
    part.referenceImageId = id + "_FL";
    part.partnerImageId = id + "_FR";
    part.runAlong = ( track[9] - track[8] ).normalized();
    part.trajectory = &track;
    return part;
  }

  //! The run's line so far: the paint 3.5 m right of the track from 75 m to 88 m, a vertex every metre.
  std::vector<TracedVertex> paintTo88m()
  {
    std::vector<TracedVertex> line;
    for ( double s = 75.0; s <= 88.0; s += 1.0 )
    {
      TracedVertex t;
      t.point = beside( s, -3.5 );
      t.covariance = Eigen::Vector3d( 0.015 * 0.015, 0.015 * 0.015, 0.02 * 0.02 ).asDiagonal();
      line.push_back( t );
    }
    return line;
  }

  /**
   * A 10 px bright stripe running up a 120 x 140 image (columns 55-64), its
   * left half worn away from row `fromRow` to `toRow`, with noise and blur.
   */
  cv::Mat stripeWornOnItsLeft( int fromRow, int toRow )
  {
    cv::Mat grey( 140, 120, CV_8UC1, cv::Scalar( 60 ) );
    cv::rectangle( grey, cv::Point( 55, 0 ), cv::Point( 64, 139 ), cv::Scalar( 200 ), cv::FILLED );
    cv::rectangle( grey, cv::Point( 55, fromRow ), cv::Point( 59, toRow ), cv::Scalar( 62 ), cv::FILLED );
    cv::Mat noise( grey.size(), CV_8SC1 );
    cv::theRNG().state = 5;
    cv::randn( noise, 0, 3 );
    cv::add( grey, noise, grey, cv::noArray(), CV_8UC1 );
    cv::GaussianBlur( grey, grey, cv::Size( 5, 5 ), 0.8 );
    return grey;
  }

  //! The seed took that stripe at its full width, through its centre line (column 60).
  void expectTheWholeStripe( const SeedAnalysis &seed )
  {
    ASSERT_TRUE( seed.ok() ) << seed.message;
    EXPECT_EQ( seed.profile.kind, LineKind::BrightStripe );
    EXPECT_NEAR( seed.profile.widthPx, 10.0, 1.5 );
    EXPECT_NEAR( seed.pixelInImage.x(), 60.0, 0.7 );
  }
}

TEST( TrackCourse, CoordinatesOnACurvedTrack )
{
  const std::vector<Eigen::Vector3d> track = curvedTrack();
  for ( const double arc : { 3.0, 10.0, 47.5, 120.0, 185.0 } )
    for ( const double left : { -4.0, 0.0, 3.5 } )
    {
      const std::optional<TrackCoordinates> c = trackCoordinates( track, beside( arc, left ).head<2>() );
      ASSERT_TRUE( c );
      // (the track is the arc's chords: 5.7 cm inside the arc between stations)
      EXPECT_NEAR( c->arcM, arc, 0.1 ) << arc << " " << left;
      EXPECT_NEAR( c->leftOffsetM, left, 0.07 ) << arc << " " << left;
    }
  // outside the bend at a station, beyond both legs' ends: still the right side and place, not the track's start
  const std::optional<TrackCoordinates> wedge = trackCoordinates( track, beside( 50.0, -4.0 ).head<2>() );
  ASSERT_TRUE( wedge );
  EXPECT_NEAR( wedge->arcM, 50.0, 0.1 );
  EXPECT_NEAR( wedge->leftOffsetM, -4.0, 0.07 );
  EXPECT_FALSE( trackCoordinates( { Eigen::Vector3d::Zero() }, Eigen::Vector2d( 1, 1 ) ) );
}

TEST( TrackCourse, TheCorridorCutsAJumpAcrossTheRoadOnly )
{
  const std::vector<Eigen::Vector3d> track = curvedTrack();
  std::mt19937 random( 5 );
  std::normal_distribution<double> noise( 0.0, 0.03 );
  // the edge line 3.5 m right of the track, followed 20 m through the curve
  std::vector<std::optional<Eigen::Vector3d>> line;
  for ( double s = 0.0; s <= 20.0; s += 0.5 )
    line.push_back( beside( 60.0 + s, -3.5 + noise( random ) ) );
  const Eigen::Vector3d anchor = *line.front();
  EXPECT_EQ( pointsInCourse( track, anchor, line, 0.6, 0.08 ), line.size() );
  // a line merging at 1:20 stays in the corridor too
  std::vector<std::optional<Eigen::Vector3d>> merging;
  for ( double s = 0.0; s <= 20.0; s += 0.5 )
    merging.push_back( beside( 60.0 + s, -3.5 + 0.05 * s ) );
  EXPECT_EQ( pointsInCourse( track, anchor, merging, 0.6, 0.08 ), merging.size() );
  // a bridge that jumped onto the lane line 6.7 m to the left after 4 m: cut where it left; points that
  // do not reach the ground are passed over
  std::vector<std::optional<Eigen::Vector3d>> jumped( line.begin(), line.begin() + 9 );
  jumped.push_back( std::nullopt );
  for ( double s = 5.0; s <= 20.0; s += 0.5 )
    jumped.push_back( beside( 60.0 + s, 3.2 ) );
  EXPECT_EQ( pointsInCourse( track, anchor, jumped, 0.6, 0.08 ), 10u );
  // no trajectory: nothing to compare with, everything kept
  EXPECT_EQ( pointsInCourse( { track.front() }, anchor, jumped, 0.6, 0.08 ), jumped.size() );
}

TEST( TrackCourse, TheLinesDirectionTurnsWithTheTrack )
{
  // a line's 20 m chord (60-80 m along the 220 m curve) points 2.6 degrees off its tangent at 80 m and 6.5
  // degrees off at 95 m; turned with the track it is the tangent there
  const std::vector<Eigen::Vector3d> track = curvedTrack();
  const auto tangent = []( double arc ) { return Eigen::Vector3d( std::cos( arc / kRadius ), std::sin( arc / kRadius ), 0.0 ); };
  const auto degreesBetween = []( const Eigen::Vector3d &a, const Eigen::Vector3d &b ) { return std::acos( std::min( 1.0, a.normalized().dot( b.normalized() ) ) ) * 180.0 / M_PI; };
  for ( const double left : { -3.5, 3.5 } )
  {
    const Eigen::Vector3d chord = ( beside( 80.0, left ) - beside( 60.0, left ) ).normalized(), middle = 0.5 * ( beside( 80.0, left ) + beside( 60.0, left ) );
    for ( const double arc : { 80.0, 95.0 } )
    {
      EXPECT_GT( degreesBetween( chord, tangent( arc ) ), 2.5 );
      EXPECT_LT( degreesBetween( lineDirectionAt( track, chord, middle, beside( arc, left ) ), tangent( arc ) ), 0.2 ) << left << " " << arc;
    }
  }
  // a line that is not parallel to the track (turned 4 degrees off it) keeps its angle to the track
  const double off = 4.0 * M_PI / 180.0;
  const auto turned = [&]( const Eigen::Vector3d &d ) { return Eigen::Vector3d( std::cos( off ) * d.x() - std::sin( off ) * d.y(), std::sin( off ) * d.x() + std::cos( off ) * d.y(), 0.0 ); };
  const Eigen::Vector3d skew = turned( tangent( 70.0 ) );
  EXPECT_NEAR( degreesBetween( lineDirectionAt( track, skew, beside( 70.0, 0.0 ), beside( 100.0, 1.0 ) ), tangent( 100.0 ) ), 4.0, 0.2 );
  // the line's slope is kept; with no track to turn with, the chord is the direction
  const Eigen::Vector3d climbing = ( tangent( 70.0 ) + Eigen::Vector3d( 0, 0, 0.05 ) ).normalized();
  EXPECT_NEAR( lineDirectionAt( track, climbing, beside( 70.0, 0.0 ), beside( 100.0, 0.0 ) ).z(), climbing.z(), 1e-9 );
  EXPECT_EQ( lineDirectionAt( { track.front() }, climbing, beside( 70.0, 0.0 ), beside( 100.0, 0.0 ) ), climbing );
}

TEST( TrackCourse, AStrayLastVertexDoesNotMoveTheRecentOffset )
{
  const std::vector<Eigen::Vector3d> track = curvedTrack();
  std::vector<Eigen::Vector3d> line;
  for ( double s = 0.0; s <= 12.0; s += 0.75 )
    line.push_back( beside( 80.0 + s, -3.5 ) );
  line.push_back( beside( 93.0, -3.8 ) ); // slid onto the kerb face beside the paint
  const std::optional<double> recent = recentTrackOffset( track, line, 10.0 );
  ASSERT_TRUE( recent );
  EXPECT_NEAR( *recent, -3.5, 0.07 );
  // continued at that offset, not at the stray vertex's
  const std::vector<Eigen::Vector3d> ahead = trajectoryContinuation( track, line.back(), 1, 10.0, 1.0, recent );
  ASSERT_EQ( ahead.size(), 10u );
  EXPECT_NEAR( trackCoordinates( track, ahead.back().head<2>() )->leftOffsetM, -3.5, 0.07 );
  EXPECT_NEAR( trackCoordinates( track, ahead.back().head<2>() )->arcM, 103.0, 0.1 );
  EXPECT_FALSE( recentTrackOffset( track, { line.back() }, 10.0 ) );
}

TEST( TrackCourse, AStationThatSlidOntoTheParallelEdgeIsCut )
{
  const std::vector<Eigen::Vector3d> track = curvedTrack();
  RoadTraceOptions options;
  const auto vertex = [&]( double arc, double left ) { return vertexBeside( arc, left, 0.015, 0.02 ); };
  StationPart part = stationPartOn( track, "S0008" );
  const std::vector<TracedVertex> line = paintTo88m();
  part.keep = line.size();
  // this station: on the paint to 92 m, one stray vertex, back on the paint, then on the kerb face 0.3 m beside it
  std::vector<LineVertex3d> station;
  for ( double s = 89.0; s <= 92.0; s += 1.0 )
    station.push_back( vertex( s, -3.5 ) );
  station.push_back( vertex( 92.5, -3.75 ) );
  station.push_back( vertex( 93.0, -3.5 ) );
  for ( double s = 94.0; s <= 100.0; s += 1.0 )
    station.push_back( vertex( s, -3.8 ) );
  std::vector<TracedVertex> run = line;
  const StationPartSummary summary = appendStationPart( run, station, part, options );
  EXPECT_EQ( summary.ownVertices, 5 );        // 89-92 m and 93 m
  EXPECT_EQ( summary.lateralOutliers, 8 );    // the stray one, and the kerb face from 94 m on
  ASSERT_EQ( run.size(), line.size() + 5 );
  EXPECT_NEAR( trackCoordinates( track, run.back().point.head<2>() )->arcM, 93.0, 0.1 );
  // without the trajectory (or with the check off) every vertex joins
  run = line;
  options.maxLateralStepM = 0.0;
  EXPECT_EQ( appendStationPart( run, station, part, options ).ownVertices, static_cast<int>( station.size() ) );
}

TEST( TrackCourse, AClickOnWornPaintPicksTheStripeNotItsSide )
{
  // a 10 px painted stripe running up the image on asphalt; at the click its left half is worn away, so
  // the side of what is left (60) is nearer the click than its centre (62.5)
  cv::Mat grey( 120, 120, CV_8UC1, cv::Scalar( 60 ) );
  cv::rectangle( grey, cv::Point( 55, 0 ), cv::Point( 64, 119 ), cv::Scalar( 200 ), cv::FILLED );
  cv::rectangle( grey, cv::Point( 55, 57 ), cv::Point( 59, 63 ), cv::Scalar( 60 ), cv::FILLED );
  cv::GaussianBlur( grey, grey, cv::Size( 5, 5 ), 0.8 );
  const SeedAnalysis worn = analyseSeed( grey, Eigen::Vector2d( 60.6, 60.0 ), 0.0 );
  ASSERT_TRUE( worn.ok() ) << worn.message;
  EXPECT_EQ( worn.profile.kind, LineKind::BrightStripe );
  EXPECT_NEAR( worn.profile.widthPx, 10.0, 1.5 ); // from the profiles either side, not the worn one
  // a kerb face: a bright band 18 px wide beside the asphalt, clicked at its foot: the edge, not the band
  cv::Mat kerb( 120, 120, CV_8UC1, cv::Scalar( 60 ) );
  cv::rectangle( kerb, cv::Point( 60, 0 ), cv::Point( 77, 119 ), cv::Scalar( 150 ), cv::FILLED );
  cv::rectangle( kerb, cv::Point( 78, 0 ), cv::Point( 119, 119 ), cv::Scalar( 110 ), cv::FILLED );
  cv::GaussianBlur( kerb, kerb, cv::Size( 5, 5 ), 0.8 );
  const SeedAnalysis foot = analyseSeed( kerb, Eigen::Vector2d( 60.8, 60.0 ), 0.0 );
  ASSERT_TRUE( foot.ok() ) << foot.message;
  EXPECT_EQ( foot.profile.kind, LineKind::Edge );
  EXPECT_NEAR( foot.pixelInImage.x(), 60.0, 1.0 );
}

TEST( TrackCourse, AClickOnAStripeWornHalfAwayOverALongStretchPicksTheStripe )
{
  // a 10 px stripe whose left half is worn away over 44 px around the click, clicked at the stripe's centre:
  // there the paint's left side is the nearest line and is found all along the worn stretch. The stripe, at
  // its full width beyond the wear, is what was meant (a seed on the side traced the whole run 7 cm off).
  const SeedAnalysis seed = analyseSeed( stripeWornOnItsLeft( 48, 91 ), Eigen::Vector2d( 60.3, 70.0 ), std::nullopt );
  expectTheWholeStripe( seed );
  EXPECT_GT( std::abs( seed.direction.y() ), std::cos( 3.0 * M_PI / 180.0 ) );
  // the same stripe unworn, and a kerb face clicked at its foot (a band as wide all along): as before
  cv::Mat whole( 140, 120, CV_8UC1, cv::Scalar( 60 ) );
  cv::rectangle( whole, cv::Point( 55, 0 ), cv::Point( 64, 139 ), cv::Scalar( 200 ), cv::FILLED );
  cv::GaussianBlur( whole, whole, cv::Size( 5, 5 ), 0.8 );
  const SeedAnalysis clean = analyseSeed( whole, Eigen::Vector2d( 60.3, 70.0 ), std::nullopt );
  EXPECT_EQ( clean.profile.kind, LineKind::BrightStripe );
  EXPECT_NEAR( clean.profile.widthPx, 10.0, 1.0 );
  EXPECT_NEAR( clean.pixelInImage.x(), 60.0, 0.5 );
  cv::Mat kerb( 140, 120, CV_8UC1, cv::Scalar( 60 ) );
  cv::rectangle( kerb, cv::Point( 60, 0 ), cv::Point( 77, 139 ), cv::Scalar( 150 ), cv::FILLED );
  cv::rectangle( kerb, cv::Point( 78, 0 ), cv::Point( 119, 139 ), cv::Scalar( 110 ), cv::FILLED );
  cv::GaussianBlur( kerb, kerb, cv::Size( 5, 5 ), 0.8 );
  const SeedAnalysis foot = analyseSeed( kerb, Eigen::Vector2d( 60.8, 70.0 ), 0.0 );
  EXPECT_EQ( foot.profile.kind, LineKind::Edge );
}

TEST( TrackCourse, AClickAtTheNearEndOfAStretchWornHalfAwayPicksTheStripe )
{
  // the same stripe worn half away from the top of the image down to 15 px below the click: the full width
  // is found only down the image (towards the camera), where perspective alone also widens a line. The
  // paint up the image is as narrow as at the click - perspective would narrow it further - so it is wear.
  const SeedAnalysis seed = analyseSeed( stripeWornOnItsLeft( 0, 85 ), Eigen::Vector2d( 60.3, 70.0 ), std::nullopt );
  expectTheWholeStripe( seed );
  // a kerb face seen in perspective - a bright band that widens down the image, 1.4 times as wide 18 px
  // below the click and narrower above it - clicked at its foot: the edge, as on a band as wide all along
  cv::Mat kerb( 140, 160, CV_8UC1, cv::Scalar( 60 ) );
  for ( int r = 0; r < 140; ++r )
  {
    const int width = std::max( 1, static_cast<int>( std::lround( 18.0 * ( r - 25.0 ) / 45.0 ) ) );
    cv::line( kerb, cv::Point( 60, r ), cv::Point( 60 + width - 1, r ), cv::Scalar( 150 ) );
    cv::line( kerb, cv::Point( 60 + width, r ), cv::Point( 159, r ), cv::Scalar( 110 ) );
  }
  cv::GaussianBlur( kerb, kerb, cv::Size( 5, 5 ), 0.8 );
  const SeedAnalysis foot = analyseSeed( kerb, Eigen::Vector2d( 60.8, 70.0 ), 0.0 );
  ASSERT_TRUE( foot.ok() ) << foot.message;
  EXPECT_EQ( foot.profile.kind, LineKind::Edge );
  EXPECT_NEAR( foot.pixelInImage.x(), 60.0, 1.0 );
  // a clean stripe narrower up the image and wider down it, as perspective makes a line (8 px at the click,
  // 14 px from 10 px below it, 3 px from 10 px above it), clicked on its left side: wider only down the image
  // and narrower up it is not wear - the edge clicked is kept, as on a stripe as wide all along
  cv::Mat narrowing( 140, 120, CV_8UC1, cv::Scalar( 60 ) );
  for ( int r = 0; r < 140; ++r )
  {
    const double half = r < 60 ? 1.5 : r <= 80 ? 4.0 : 7.0;
    for ( int c = 0; c < 120; ++c )
    {
      // the stripe's cover of each pixel
      const double cover = std::clamp( std::min( c + 1.0, 60.0 + half ) - std::max( static_cast<double>( c ), 60.0 - half ), 0.0, 1.0 );
      narrowing.at<uchar>( r, c ) = cv::saturate_cast<uchar>( 60.0 + 140.0 * cover );
    }
  }
  cv::GaussianBlur( narrowing, narrowing, cv::Size( 5, 5 ), 0.8 );
  const SeedAnalysis side = analyseSeed( narrowing, Eigen::Vector2d( 56.3, 70.0 ), 0.0 );
  ASSERT_TRUE( side.ok() ) << side.message;
  EXPECT_EQ( side.profile.kind, LineKind::Edge );
  EXPECT_NEAR( side.pixelInImage.x(), 56.0, 1.0 );
}

TEST( TrackCourse, AVertexBeyondAGapKeepsTheLinesCourse )
{
  // a station's follower lost the line at 90 m in a shadow and bridged 11 m onto the parallel edge 1.1 m
  // beside it: with nothing of the line within 10 m before it, the vertex there is held to the course of the
  // nearest vertices before the gap, the allowance grown by 2 % of the gap
  const std::vector<Eigen::Vector3d> track = curvedTrack();
  RoadTraceOptions options;
  const auto vertex = [&]( double arc, double left ) { return vertexBeside( arc, left, 0.02, 0.03 ); };
  StationPart part = stationPartOn( track, "S0009" );
  const std::vector<TracedVertex> line = paintTo88m();
  part.keep = line.size();
  const std::vector<LineVertex3d> astray { vertex( 89.0, -3.5 ), vertex( 89.5, -3.5 ), vertex( 90.0, -3.5 ), vertex( 101.0, -2.4 ) };
  std::vector<TracedVertex> run = line;
  StationPartSummary summary = appendStationPart( run, astray, part, options );
  EXPECT_EQ( summary.ownVertices, 3 );
  EXPECT_EQ( summary.lateralOutliers, 1 );
  EXPECT_NEAR( trackCoordinates( track, run.back().point.head<2>() )->arcM, 90.0, 0.1 );
  // the line itself beyond the same gap (a 5 cm drift) joins
  const std::vector<LineVertex3d> onCourse { vertex( 89.0, -3.5 ), vertex( 89.5, -3.5 ), vertex( 90.0, -3.5 ), vertex( 101.0, -3.55 ) };
  run = line;
  summary = appendStationPart( run, onCourse, part, options );
  EXPECT_EQ( summary.ownVertices, 4 );
  EXPECT_EQ( summary.lateralOutliers, 0 );
  // beyond a gap of more than 30 m nothing is known of the course there: the vertex joins
  const std::vector<LineVertex3d> farBeyond { vertex( 89.0, -3.5 ), vertex( 89.5, -3.5 ), vertex( 90.0, -3.5 ), vertex( 125.0, -2.4 ) };
  run = line;
  EXPECT_EQ( appendStationPart( run, farBeyond, part, options ).ownVertices, 4 );
}

TEST( TrackCourse, AClickOnALongCrackAcrossAStripeFindsTheStripe )
{
  // a 10 px painted stripe at 35 degrees, worn across for 28 px at the click down to a 3 px sliver off its
  // centre, cracked across twice: the lines nearest the click are the cracks' and the sliver's edges, found
  // along no direction beyond the worn part; the stripe is found beyond it, through the click
  cv::Mat upright( 240, 240, CV_8UC1, cv::Scalar( 70 ) );
  cv::rectangle( upright, cv::Point( 115, 0 ), cv::Point( 124, 239 ), cv::Scalar( 190 ), cv::FILLED );
  cv::rectangle( upright, cv::Point( 115, 106 ), cv::Point( 124, 133 ), cv::Scalar( 75 ), cv::FILLED );
  cv::rectangle( upright, cv::Point( 117, 106 ), cv::Point( 119, 133 ), cv::Scalar( 185 ), cv::FILLED );
  cv::line( upright, cv::Point( 112, 112 ), cv::Point( 126, 116 ), cv::Scalar( 60 ), 2 );
  cv::line( upright, cv::Point( 112, 124 ), cv::Point( 126, 128 ), cv::Scalar( 60 ), 2 );
  cv::Mat grey;
  // (turned about the stripe's centre line, x 119.5 in OpenCV's pixel-centre coordinates, 120.0 in ours)
  cv::warpAffine( upright, grey, cv::getRotationMatrix2D( cv::Point2f( 119.5f, 119.5f ), -35.0, 1.0 ), upright.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE );
  cv::Mat noise( grey.size(), CV_8SC1 );
  cv::theRNG().state = 7;
  cv::randn( noise, 0, 3 );
  cv::add( grey, noise, grey, cv::noArray(), CV_8UC1 );
  cv::GaussianBlur( grey, grey, cv::Size( 5, 5 ), 0.8 );
  const Eigen::Vector2d click( 120.0, 120.0 );
  const SeedAnalysis seed = analyseSeed( grey, click, std::nullopt );
  ASSERT_TRUE( seed.ok() ) << seed.message;
  EXPECT_EQ( seed.profile.kind, LineKind::BrightStripe );
  EXPECT_NEAR( seed.profile.widthPx, 10.0, 2.0 );
  // the stripe runs up the image turned 35 degrees clockwise
  const Eigen::Vector2d along( std::sin( 35.0 * M_PI / 180.0 ), -std::cos( 35.0 * M_PI / 180.0 ) );
  EXPECT_GT( std::abs( seed.direction.dot( along ) ), std::cos( 4.0 * M_PI / 180.0 ) );
  EXPECT_LT( std::abs( ( seed.pixelInImage - click ).dot( Eigen::Vector2d( -along.y(), along.x() ) ) ), 1.5 );
}

TEST( TrackCourse, AStationsFirstVerticesAstrayDoNotTakeTheRest )
{
  // a station followed its line back towards its camera from the start and strayed there: its first two
  // vertices lie 0.2 m off the line, the rest on it. The two go; the rest, back on the course, stay.
  const std::vector<Eigen::Vector3d> track = curvedTrack();
  RoadTraceOptions options;
  const auto vertex = [&]( double arc, double left ) { return vertexBeside( arc, left, 0.015, 0.02 ); };
  StationPart part = stationPartOn( track, "S0009" );
  const std::vector<TracedVertex> line = paintTo88m();
  part.keep = line.size();
  std::vector<LineVertex3d> station { vertex( 89.0, -3.7 ), vertex( 89.5, -3.68 ) };
  for ( double s = 90.0; s <= 96.0; s += 1.0 )
    station.push_back( vertex( s, -3.5 ) );
  std::vector<TracedVertex> run = line;
  const StationPartSummary summary = appendStationPart( run, station, part, options );
  EXPECT_EQ( summary.lateralOutliers, 2 );
  EXPECT_EQ( summary.ownVertices, 7 );
  EXPECT_NEAR( trackCoordinates( track, run[line.size()].point.head<2>() )->arcM, 90.0, 0.1 );
}
