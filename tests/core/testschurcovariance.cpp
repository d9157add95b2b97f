// Schur-complement covariances equal the blocks of the dense inverse.
#include <random>

#include <Eigen/Dense>
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "adjustment/internal/collinearityerror.h"
#include "adjustment/internal/priors.h"
#include "adjustment/schurcovariance.h"
#include "vanrig.h"

using namespace geostation;

TEST( SchurCovariance, EqualsTheDenseInverse )
{
  const auto images = vanrig::images();
  std::mt19937 rng( 1 );
  std::vector<std::array<double, 6>> poses;
  for ( const auto &image : images )
  {
    const ExteriorOrientation &eo = image->exterior();
    poses.push_back( { eo.projectionCentre.x() - 500000.0, eo.projectionCentre.y() - 4400000.0, eo.projectionCentre.z() - 100.0,
                       degToRad( eo.omegaDeg ), degToRad( eo.phiDeg ), degToRad( eo.kappaDeg ) } );
  }
  std::vector<std::array<double, kInteriorSize>> interiors( images.size() );
  std::vector<std::array<double, 3>> points;
  ceres::Problem problem;
  for ( size_t i = 0; i < images.size(); ++i )
  {
    interiorBlockFromCamera( images[i]->camera(), interiors[i].data() );
    problem.AddParameterBlock( interiors[i].data(), kInteriorSize );
    problem.SetParameterBlockConstant( interiors[i].data() );
  }
  points.reserve( 12 );
  for ( int j = 0; j < 12; ++j )
  {
    const Eigen::Vector3d p = vanrig::pointAhead( rng );
    points.push_back( { p.x() - 500000.0, p.y() - 4400000.0, p.z() - 100.0 } );
    for ( size_t i = 0; i < images.size(); ++i )
    {
      const Eigen::Vector2d pixel = images[i]->projectGroundToPixel( p ).pixelInImage;
      problem.AddResidualBlock( CollinearityError::create( images[i]->camera(), pixel.x(), pixel.y(), 0.5 ), nullptr, poses[i].data(), interiors[i].data(), points.back().data() );
    }
  }
  // A datum: priors on every pose, one pose with a fixed component.
  for ( size_t i = 0; i < images.size(); ++i )
    problem.AddResidualBlock( ParameterPrior<6>::create( poses[i], { 0.1, 0.1, 0.1, 0.001, 0.001, i == 2 ? 0.0 : 0.001 } ), nullptr, poses[i].data() );
  problem.SetManifold( poses[2].data(), new ceres::SubsetManifold( 6, { 5 } ) );

  std::vector<double *> cameraBlocks, pointBlocks;
  for ( auto &p : poses )
    cameraBlocks.push_back( p.data() );
  for ( auto &p : points )
    pointBlocks.push_back( p.data() );
  const SchurCovariance schur = schurCovariance( problem, cameraBlocks, pointBlocks );
  ASSERT_TRUE( schur.ok );

  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = cameraBlocks;
  options.parameter_blocks.insert( options.parameter_blocks.end(), pointBlocks.begin(), pointBlocks.end() );
  ceres::CRSMatrix crs;
  ASSERT_TRUE( problem.Evaluate( options, nullptr, nullptr, nullptr, &crs ) );
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero( crs.num_rows, crs.num_cols );
  for ( int r = 0; r < crs.num_rows; ++r )
    for ( int k = crs.rows[r]; k < crs.rows[r + 1]; ++k )
      J( r, crs.cols[k] ) = crs.values[k];
  const Eigen::MatrixXd dense = ( J.transpose() * J ).inverse();
  const int cameraColumns = 6 * static_cast<int>( images.size() ) - 1;
  ASSERT_EQ( schur.cameras.rows(), cameraColumns );
  EXPECT_LT( ( schur.cameras - dense.topLeftCorner( cameraColumns, cameraColumns ) ).norm(), 1e-9 * dense.topLeftCorner( cameraColumns, cameraColumns ).norm() );
  for ( size_t j = 0; j < points.size(); ++j )
  {
    const Eigen::Matrix3d expected = dense.block<3, 3>( cameraColumns + 3 * j, cameraColumns + 3 * j );
    EXPECT_LT( ( schur.points[j] - expected ).norm(), 1e-9 * expected.norm() ) << j;
  }
}
