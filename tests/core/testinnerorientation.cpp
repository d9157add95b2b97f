// Inner orientation: the paper's decomposition, recovery of a known scan
// affine, residuals, and failures.
#include <random>

#include <Eigen/Dense>

#include <gtest/gtest.h>

#include "adjustment/innerorientation.h"
#include "geometry/rotation.h"

using namespace geostation;

namespace
{
  Eigen::Matrix2d rotation( double deg )
  {
    const double c = std::cos( degToRad( deg ) ), s = std::sin( degToRad( deg ) );
    Eigen::Matrix2d r;
    r << c, -s, s, c;
    return r;
  }

  //! The paper's composition: rotation beta after stretching by A, B along alpha.
  Eigen::Matrix2d compose( double A, double B, double alphaDeg, double betaDeg )
  {
    Eigen::Matrix2d paperRotation;
    const double cb = std::cos( degToRad( betaDeg ) ), sb = std::sin( degToRad( betaDeg ) );
    paperRotation << cb, sb, -sb, cb;
    return paperRotation * rotation( alphaDeg ) * Eigen::DiagonalMatrix<double, 2>( A, B ) * rotation( alphaDeg ).transpose();
  }

  //! Eight fiducials of a 230 mm aerial camera: corners and side midpoints.
  std::vector<Fiducial> aerialFiducials()
  {
    return { { "1", { -106.0, 106.0 } }, { "2", { 106.0, 106.0 } }, { "3", { 106.0, -106.0 } }, { "4", { -106.0, -106.0 } },
      { "5", { 0.0, 112.0 } }, { "6", { 112.0, 0.0 } }, { "7", { 0.0, -112.0 } }, { "8", { -112.0, 0.0 } } };
  }
} // namespace

TEST( InnerOrientation, DecompositionFollowsThePaper )
{
  std::mt19937 rng( 1 );
  std::uniform_real_distribution<double> angle( -80.0, 80.0 ), scale( 0.01, 0.03 ), affinity( 1.0, 1.01 );
  for ( int i = 0; i < 500; ++i )
  {
    const double B = scale( rng ), A = B * affinity( rng ), alpha = angle( rng ), beta = angle( rng ) * 2.0;
    const AffineDecomposition d = decomposeAffine( compose( A, B, alpha, beta ) );
    EXPECT_NEAR( d.scaleA, A, 1e-12 );
    EXPECT_NEAR( d.scaleB, B, 1e-12 );
    EXPECT_NEAR( d.betaDeg, beta, 1e-9 );
    EXPECT_NEAR( d.affinityPct, 100.0 * ( A / B - 1.0 ), 1e-8 );
    if ( A / B - 1.0 > 1e-4 ) // alpha is undefined for a similarity
    {
      EXPECT_NEAR( d.alphaADeg, alpha, 1e-6 ) << A / B;
    }
    EXPECT_NEAR( d.alphaBDeg, d.alphaADeg + 90.0, 1e-12 );
    // And the pieces compose back to the matrix.
    EXPECT_LT( ( compose( d.scaleA, d.scaleB, d.alphaADeg, d.betaDeg ) - compose( A, B, alpha, beta ) ).norm(), 1e-12 );
  }
}

TEST( InnerOrientation, RecoversAScanAffine )
{
  // A 12.5 um scan rotated 0.8 degrees with 0.3 % affinity, centred at (9200, 9150) px.
  const Eigen::Matrix2d a = compose( 0.0125 * 1.003, 0.0125, 25.0, 0.8 );
  const Eigen::Vector2d centrePx( 9200.0, 9150.0 ), uv0( 9200.0, -9150.0 );
  std::vector<FiducialMeasurement> measured;
  std::mt19937 rng( 2 );
  std::normal_distribution<double> noise( 0.0, 0.3 );
  for ( const Fiducial &f : aerialFiducials() )
  {
    const Eigen::Vector2d uv = uv0 + a.inverse() * f.photoMm;
    measured.push_back( { f.id, Eigen::Vector2d( uv.x(), -uv.y() ) } );
  }
  const InnerOrientationSummary exact = innerOrientation( aerialFiducials(), measured );
  ASSERT_TRUE( exact.ok() ) << exact.message;
  EXPECT_LT( ( exact.a - a ).norm(), 1e-12 );
  EXPECT_NEAR( exact.decomposition.betaDeg, 0.8, 1e-9 );
  EXPECT_NEAR( exact.decomposition.affinityPct, 0.3, 1e-7 );
  EXPECT_NEAR( exact.decomposition.alphaADeg, 25.0, 1e-6 );
  EXPECT_LT( exact.rmsResidualMm, 1e-10 );
  EXPECT_EQ( exact.redundancy, 10 );
  // The principal point region: the fiducial centre maps to photo (0, 0).
  EXPECT_LT( exact.photoMmFromPixel( centrePx ).norm(), 1e-9 );
  EXPECT_LT( ( exact.photoMmFromPixel( measured[0].pixelInImage ) - Eigen::Vector2d( -106.0, 106.0 ) ).norm(), 1e-9 );

  // With 0.3 px measurement noise, sigma0 is about 0.3 px times the scale.
  for ( FiducialMeasurement &m : measured )
    m.pixelInImage += Eigen::Vector2d( noise( rng ), noise( rng ) );
  const InnerOrientationSummary noisy = innerOrientation( aerialFiducials(), measured );
  ASSERT_TRUE( noisy.ok() );
  EXPECT_GT( noisy.sigma0Mm, 0.1 * 0.3 * 0.0125 );
  EXPECT_LT( noisy.sigma0Mm, 3.0 * 0.3 * 0.0125 );
  EXPECT_NEAR( noisy.decomposition.betaDeg, 0.8, 0.01 );
}

TEST( InnerOrientation, FailuresAreReported )
{
  std::vector<FiducialMeasurement> two { { "1", { 100, 100 } }, { "2", { 18000, 100 } } };
  EXPECT_EQ( innerOrientation( aerialFiducials(), two ).status, InnerOrientationSummary::Status::TooFewFiducials );

  std::vector<FiducialMeasurement> line { { "1", { 100, 100 } }, { "5", { 9000, 100 } }, { "2", { 18000, 100 } } };
  EXPECT_EQ( innerOrientation( aerialFiducials(), line ).status, InnerOrientationSummary::Status::Degenerate );

  // Ids of left and right swapped: a mirrored solution.
  std::vector<FiducialMeasurement> mirrored { { "2", { 100, 100 } }, { "1", { 18000, 100 } }, { "4", { 18000, 18000 } }, { "3", { 100, 18000 } } };
  const InnerOrientationSummary m = innerOrientation( aerialFiducials(), mirrored );
  EXPECT_EQ( m.status, InnerOrientationSummary::Status::Degenerate );
  EXPECT_NE( m.message.find( "mirrored" ), std::string::npos );

  EXPECT_THROW( innerOrientation( aerialFiducials(), { { "9", { 1, 1 } } } ), std::invalid_argument );
  EXPECT_THROW( innerOrientation( aerialFiducials(), { { "1", { 1, 1 } }, { "1", { 2, 2 } } } ), std::invalid_argument );
}
