/***************************************************************************
  testpolyline.cpp - the nearest point of a polyline (geometry/polyline.h),
  the one every module uses: in image space, in object space and in plan
 ***************************************************************************/
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/polyline.h"

using namespace geostation;

TEST( Polyline, TheNearestPointSaysWhereItLies )
{
  const std::vector<Eigen::Vector2d> line = { { 0, 0 }, { 10, 0 }, { 10, 10 } };
  const PolylineNearest onSecond = nearestOnPolyline( line, Eigen::Vector2d( 13, 4 ) );
  EXPECT_DOUBLE_EQ( onSecond.distance, 3.0 );
  EXPECT_EQ( onSecond.segment, 1u );
  EXPECT_DOUBLE_EQ( onSecond.t, 0.4 );
  EXPECT_TRUE( onSecond.direction.isApprox( Eigen::Vector2d( 0, 1 ) ) );
  // beyond the first vertex: clamped to it
  const PolylineNearest before = nearestOnPolyline( line, Eigen::Vector2d( -3, 4 ) );
  EXPECT_DOUBLE_EQ( before.distance, 5.0 );
  EXPECT_EQ( before.segment, 0u );
  EXPECT_DOUBLE_EQ( before.t, 0.0 );
}

TEST( Polyline, APointAndARepeatedVertexHaveNoDirection )
{
  const PolylineNearest point = nearestOnPolyline( std::vector<Eigen::Vector2d> { { 1, 1 } }, Eigen::Vector2d( 4, 5 ) );
  EXPECT_DOUBLE_EQ( point.distance, 5.0 );
  EXPECT_TRUE( point.direction.isZero() );
  const PolylineNearest repeated = nearestOnPolyline( std::vector<Eigen::Vector2d> { { 1, 1 }, { 1, 1 } }, Eigen::Vector2d( 4, 5 ) );
  EXPECT_DOUBLE_EQ( repeated.distance, 5.0 );
  EXPECT_TRUE( repeated.direction.isZero() );
  EXPECT_TRUE( std::isinf( nearestOnPolyline( std::vector<Eigen::Vector2d>(), Eigen::Vector2d( 0, 0 ) ).distance ) );
  EXPECT_DOUBLE_EQ( nearestOnSegment( Eigen::Vector2d( 2, 2 ), Eigen::Vector2d( 2, 2 ), Eigen::Vector2d( 5, 6 ) ), 0.0 );
}

TEST( Polyline, InObjectSpaceAndInPlan )
{
  const std::vector<Eigen::Vector3d> line = { { 0, 0, 0 }, { 10, 0, 10 } };
  // in space the height counts; in plan it does not
  const NearestOnPolyline<Eigen::Vector3d> inSpace = nearestOnPolyline( line, Eigen::Vector3d( 5, 2, 0 ) );
  EXPECT_NEAR( inSpace.distance, std::sqrt( 2.0 * 2.5 * 2.5 + 4.0 ), 1e-12 );
  EXPECT_DOUBLE_EQ( inSpace.t, 0.25 );
  EXPECT_TRUE( inSpace.direction.isApprox( Eigen::Vector3d( 1, 0, 1 ).normalized() ) );
  const PolylineNearest inPlan = nearestOnPolylineXY( line, Eigen::Vector2d( 5, 2 ) );
  EXPECT_DOUBLE_EQ( inPlan.distance, 2.0 );
  EXPECT_DOUBLE_EQ( inPlan.t, 0.5 );
  EXPECT_TRUE( inPlan.direction.isApprox( Eigen::Vector2d( 1, 0 ) ) );
  EXPECT_DOUBLE_EQ( distanceToSegment( Eigen::Vector2d( 5, 2 ), Eigen::Vector2d( 0, 0 ), Eigen::Vector2d( 10, 0 ) ), 2.0 );
}
