// Camera model speed: ground -> pixel and pixel -> ray for each lens model,
// with OpenCV's projectPoints on the same points as the baseline.
// Prints points per second and the ratio against the baseline.
#include <map>
#include <random>

#include <benchmark/benchmark.h>

#include "benchutils.h"
#include <opencv2/calib3d.hpp>

#include "geometry/projection.h"

using namespace geostation;

namespace
{
  constexpr int kPoints = 100000;

  Camera camera( DistortionModel model )
  {
    Camera c;
    c.id = "bench";
    c.width = 1920;
    c.height = 1080;
    c.f = 1400.0;
    c.cx = 961.3;
    c.cy = 538.2;
    c.pixelSizeMm = 0.0055;
    c.distortion.model = model;
    if ( model == DistortionModel::OpenCV )
      c.distortion.coeffs = { -0.21, 0.05, 0.0006, -0.0004, 0.0 };
    if ( model == DistortionModel::BrownPhoto )
      c.distortion.coeffs = { 2e-3, -1e-5, 1e-5, -2e-5, 0.0 };
    return c;
  }

  ExteriorOrientation pose()
  {
    ExteriorOrientation eo;
    eo.projectionCentre = { 500000.0, 4400000.0, 102.5 };
    eo.omegaDeg = 84.0;
    eo.phiDeg = 1.5;
    eo.kappaDeg = -3.0;
    return eo;
  }

  //! Ground points in front of the camera, spread over the frame.
  const std::vector<Eigen::Vector3d> &groundPoints()
  {
    static const std::vector<Eigen::Vector3d> points = []
    {
      std::mt19937 rng( 1 );
      std::uniform_real_distribution<double> u( -0.6, 0.6 );
      std::uniform_real_distribution<double> depth( 3.0, 60.0 );
      const ExteriorOrientation eo = pose();
      std::vector<Eigen::Vector3d> out;
      for ( int i = 0; i < kPoints; ++i )
      {
        const double d = depth( rng );
        out.push_back( eo.projectionCentre + eo.worldDirectionFromCamera( Eigen::Vector3d( u( rng ) * d, 0.5 * u( rng ) * d, -d ) ) );
      }
      return out;
    }();
    return points;
  }

  void BM_OpenCvProjectPoints( benchmark::State &state )
  {
    const Camera c = camera( DistortionModel::OpenCV );
    const ExteriorOrientation eo = pose();
    // The same pose in OpenCV's frame: x right, y down, z forward.
    const Eigen::Matrix3d cvFromWorld = Eigen::DiagonalMatrix<double, 3>( 1, -1, -1 ) * eo.worldFromCamera().transpose();
    cv::Matx33d R;
    for ( int r = 0; r < 3; ++r )
      for ( int k = 0; k < 3; ++k )
        R( r, k ) = cvFromWorld( r, k );
    cv::Vec3d rvec;
    cv::Rodrigues( R, rvec );
    const Eigen::Vector3d t = -cvFromWorld * eo.projectionCentre;
    const cv::Vec3d tvec( t.x(), t.y(), t.z() );
    const cv::Matx33d K( c.fx(), 0, c.cx - 0.5, 0, c.fy(), c.cy - 0.5, 0, 0, 1 );
    const std::vector<double> dist { c.distortion.k1(), c.distortion.k2(), c.distortion.p1(), c.distortion.p2(), c.distortion.k3() };
    std::vector<cv::Point3d> points;
    for ( const Eigen::Vector3d &p : groundPoints() )
      points.emplace_back( p.x(), p.y(), p.z() );
    std::vector<cv::Point2d> pixels;
    for ( auto _ : state )
    {
      cv::projectPoints( points, rvec, tvec, K, dist, pixels );
      benchmark::DoNotOptimize( pixels.data() );
    }
    state.SetItemsProcessed( state.iterations() * kPoints );
  }

  void BM_GroundToPixel( benchmark::State &state )
  {
    const Camera c = camera( static_cast<DistortionModel>( state.range( 0 ) ) );
    const OrientedImage image( c, pose() );
    const std::vector<Eigen::Vector3d> &points = groundPoints();
    for ( auto _ : state )
    {
      double sum = 0.0;
      for ( const Eigen::Vector3d &p : points )
        sum += image.projectGroundToPixel( p ).pixelInImage.x();
      benchmark::DoNotOptimize( sum );
    }
    state.SetItemsProcessed( state.iterations() * kPoints );
    state.SetLabel( distortionModelName( c.distortion.model ) );
  }

  void BM_PixelToRay( benchmark::State &state )
  {
    const Camera c = camera( static_cast<DistortionModel>( state.range( 0 ) ) );
    std::vector<Eigen::Vector2d> pixels;
    std::mt19937 rng( 2 );
    std::uniform_real_distribution<double> col( 0, c.width ), row( 0, c.height );
    for ( int i = 0; i < kPoints; ++i )
      pixels.emplace_back( col( rng ), row( rng ) );
    for ( auto _ : state )
    {
      double sum = 0.0;
      for ( const Eigen::Vector2d &px : pixels )
        sum += c.rayInCameraFromPixel( px )->x();
      benchmark::DoNotOptimize( sum );
    }
    state.SetItemsProcessed( state.iterations() * kPoints );
    state.SetLabel( distortionModelName( c.distortion.model ) );
  }

} // namespace

BENCHMARK( BM_OpenCvProjectPoints )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_GroundToPixel )->Arg( static_cast<int>( DistortionModel::None ) )->Arg( static_cast<int>( DistortionModel::OpenCV ) )->Arg( static_cast<int>( DistortionModel::BrownPhoto ) )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_PixelToRay )->Arg( static_cast<int>( DistortionModel::None ) )->Arg( static_cast<int>( DistortionModel::OpenCV ) )->Arg( static_cast<int>( DistortionModel::BrownPhoto ) )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    const double baseline = benchutils::rate( rates, "BM_OpenCvProjectPoints" );
    if ( baseline <= 0.0 )
      return;
    printf( "\nPoints per second, and ratio to cv::projectPoints on the same points (baseline, this run):\n" );
    for ( const auto &[name, value] : rates )
      printf( "  %-48s %12.3g /s   x%.2f\n", name.c_str(), value, value / baseline );
  } );
}
