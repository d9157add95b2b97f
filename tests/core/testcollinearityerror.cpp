// The collinearity functor: zero residual at the truth, a hand-computed
// residual, and Ceres' gradient check, for each lens model.
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include "adjustment/internal/collinearityerror.h"
#include "vanrig.h"

using namespace geostation;

namespace
{
  struct Blocks
  {
    double pose[6];
    double interior[kInteriorSize];
    double point[3];
  };

  Blocks blocks( const Camera &camera, const ExteriorOrientation &eo, const Eigen::Vector3d &point, const Eigen::Vector3d &origin )
  {
    Blocks b;
    const Eigen::Vector3d centre = eo.projectionCentre - origin;
    b.pose[0] = centre.x();
    b.pose[1] = centre.y();
    b.pose[2] = centre.z();
    b.pose[3] = degToRad( eo.omegaDeg );
    b.pose[4] = degToRad( eo.phiDeg );
    b.pose[5] = degToRad( eo.kappaDeg );
    interiorBlockFromCamera( camera, b.interior );
    const Eigen::Vector3d p = point - origin;
    b.point[0] = p.x();
    b.point[1] = p.y();
    b.point[2] = p.z();
    return b;
  }
} // namespace

class CollinearityErrorTest : public ::testing::TestWithParam<DistortionModel>
{
};

TEST_P( CollinearityErrorTest, ZeroAtTheTruthAndProportionalToAShift )
{
  const auto images = vanrig::images();
  const OrientedImage &image = GetParam() == DistortionModel::OpenCV ? *images[0] : GetParam() == DistortionModel::None ? *images[1] : *images[2];
  const Eigen::Vector3d truth( 500000.4, 4400020.0, 101.3 ), origin( 500000.0, 4400010.0, 100.0 );
  const Eigen::Vector2d pixel = image.projectGroundToPixel( truth ).pixelInImage;
  Blocks b = blocks( image.camera(), image.exterior(), truth, origin );
  const double *parameters[3] = { b.pose, b.interior, b.point };

  std::unique_ptr<ceres::CostFunction> atTruth( CollinearityError::create( image.camera(), pixel.x(), pixel.y(), 0.5 ) );
  double residual[2];
  ASSERT_TRUE( atTruth->Evaluate( parameters, residual, nullptr ) );
  EXPECT_NEAR( residual[0], 0.0, 1e-8 );
  EXPECT_NEAR( residual[1], 0.0, 1e-8 );

  // Observed 1.5 px right and 0.8 px down of the truth, sigma 0.5: the pixel
  // residual (projected - observed) is (-1.5, -0.8) px, whitened (-3, -1.6)
  // (to first order for brown_photo, whose residual is formed in photo space).
  std::unique_ptr<ceres::CostFunction> shifted( CollinearityError::create( image.camera(), pixel.x() + 1.5, pixel.y() + 0.8, 0.5 ) );
  ASSERT_TRUE( shifted->Evaluate( parameters, residual, nullptr ) );
  const double tolerance = GetParam() == DistortionModel::BrownPhoto ? 0.05 : 1e-8;
  EXPECT_NEAR( residual[0], -3.0, tolerance );
  EXPECT_NEAR( residual[1], -1.6, tolerance );
}

TEST_P( CollinearityErrorTest, GradientsAgreeWithFiniteDifferences )
{
  const auto images = vanrig::images();
  const OrientedImage &image = GetParam() == DistortionModel::OpenCV ? *images[0] : GetParam() == DistortionModel::None ? *images[1] : *images[2];
  const Eigen::Vector3d truth( 499999.2, 4400025.0, 103.1 ), origin( 500000.0, 4400010.0, 100.0 );
  const Eigen::Vector2d pixel = image.projectGroundToPixel( truth ).pixelInImage + Eigen::Vector2d( 0.7, -0.4 );
  Blocks b = blocks( image.camera(), image.exterior(), truth, origin );
  const double *parameters[3] = { b.pose, b.interior, b.point };
  std::unique_ptr<ceres::CostFunction> cost( CollinearityError::create( image.camera(), pixel.x(), pixel.y(), 0.5 ) );
  ceres::NumericDiffOptions numericOptions;
  const std::vector<const ceres::Manifold *> *noManifolds = nullptr;
  ceres::GradientChecker checker( cost.get(), noManifolds, numericOptions );
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE( checker.Probe( parameters, 1e-6, &results ) ) << results.error_log;
}

INSTANTIATE_TEST_SUITE_P( AllModels, CollinearityErrorTest,
                          ::testing::Values( DistortionModel::None, DistortionModel::OpenCV, DistortionModel::BrownPhoto ),
                          []( const auto & info ) { return distortionModelName( info.param ); } );
