// Epipolar curves: the conjugate point lies on the curve, segments are short,
// every vertex is a point of the ray, and the curve breaks where it must.
#include <random>

#include <gtest/gtest.h>

#include "geometry/epipolar.h"
#include "vanrig.h"

using namespace geostation;

TEST( Epipolar, TheConjugatePointLiesOnTheCurve )
{
  const auto images = vanrig::images();
  std::mt19937 rng( 5 );
  for ( int trial = 0; trial < 50; ++trial )
  {
    const Eigen::Vector3d truth = vanrig::pointAhead( rng );
    for ( size_t a = 0; a < images.size(); ++a )
      for ( size_t b = 0; b < images.size(); ++b )
      {
        if ( a == b )
          continue;
        const Eigen::Vector2d pa = images[a]->projectGroundToPixel( truth ).pixelInImage;
        const Eigen::Vector2d pb = images[b]->projectGroundToPixel( truth ).pixelInImage;
        EpipolarOptions options;
        options.maxSegmentPx = 1.0;
        const EpipolarCurve curve = epipolarCurve( *images[a], pa, *images[b], options );
        ASSERT_FALSE( curve.pieces.empty() );
        double distanceAlongRay = 0.0;
        // Chords of a curve densified to 1 px stay within a few thousandths of a pixel.
        EXPECT_LT( curve.distanceToCurvePx( pb, &distanceAlongRay ), 0.01 ) << a << " -> " << b;
        EXPECT_NEAR( distanceAlongRay, ( truth - images[a]->exterior().projectionCentre ).norm(), 0.05 * distanceAlongRay );
      }
  }
}

TEST( Epipolar, DensifiedAndOnTheRay )
{
  const auto images = vanrig::images();
  const OrientedImage &left = *images[0], &right = *images[2];
  const Eigen::Vector2d pixel( 700.0, 520.0 );
  EpipolarOptions options;
  options.minDistanceM = 2.0;
  options.maxDistanceM = 50.0;
  options.maxSegmentPx = 2.0;
  const EpipolarCurve curve = epipolarCurve( left, pixel, right, options );
  ASSERT_EQ( curve.pieces.size(), 1u );
  const auto &piece = curve.pieces.front();
  EXPECT_GT( piece.size(), 20u );
  EXPECT_NEAR( piece.front().distanceM, 2.0, 1e-9 );
  EXPECT_NEAR( piece.back().distanceM, 50.0, 1e-9 );
  const Ray ray = *left.worldRayFromPixel( pixel );
  for ( size_t i = 0; i < piece.size(); ++i )
  {
    if ( i > 0 )
    {
      EXPECT_LE( ( piece[i].pixelInImage - piece[i - 1].pixelInImage ).norm(), 2.0 + 1e-9 );
      EXPECT_GT( piece[i].distanceM, piece[i - 1].distanceM );
    }
    // Each vertex is the projection of the point of the ray at its distance.
    const GroundProjection g = right.projectGroundToPixel( ray.origin + piece[i].distanceM * ray.direction );
    EXPECT_LT( ( g.pixelInImage - piece[i].pixelInImage ).norm(), 1e-9 );
  }
}

TEST( Epipolar, BreaksBehindTheOtherCamera )
{
  // Second station looks at points 2-50 m ahead of the first; near ones are behind it.
  const auto images = vanrig::images();
  const OrientedImage &first = *images[1], &ahead = *images[4];
  const EpipolarCurve curve = epipolarCurve( first, { 641.3, 600.0 }, ahead );
  ASSERT_FALSE( curve.pieces.empty() );
  EXPECT_GT( curve.pieces.front().front().distanceM, 4.0 ); // the first ~5 m are behind the second station
  EXPECT_LT( curve.pieces.front().front().distanceM, 7.0 );
}

TEST( Epipolar, BadOptionsThrow )
{
  const auto images = vanrig::images();
  EpipolarOptions options;
  options.minDistanceM = 10.0;
  options.maxDistanceM = 5.0;
  EXPECT_THROW( epipolarCurve( *images[0], { 10, 10 }, *images[1], options ), std::invalid_argument );
  options.minDistanceM = 0.0;
  options.maxDistanceM = 5.0;
  EXPECT_THROW( epipolarCurve( *images[0], { 10, 10 }, *images[1], options ), std::invalid_argument );
}

TEST( Epipolar, AVertexBudgetNeverDropsTheFarEnd )
{
  const auto images = vanrig::images();
  EpipolarOptions options;
  options.maxSegmentPx = 0.01; // would need thousands of vertices
  options.maxVertices = 100;
  const EpipolarCurve curve = epipolarCurve( *images[0], { 700.0, 520.0 }, *images[2], options );
  ASSERT_EQ( curve.pieces.size(), 1u );
  EXPECT_LE( curve.vertexCount(), 100u + 65u );
  EXPECT_NEAR( curve.pieces.front().front().distanceM, 2.0, 1e-9 );
  EXPECT_NEAR( curve.pieces.front().back().distanceM, 50.0, 1e-9 );
}
