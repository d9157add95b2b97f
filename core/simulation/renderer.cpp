/***************************************************************************
  renderer.cpp - adaptive anti-aliased ray casting of a simulated image
 ***************************************************************************/
#include "simulation/renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <thread>

namespace geostation
{

  CameraRays::CameraRays( const Camera &camera )
  {
    mStep = static_cast<long>( camera.width ) * camera.height > 4'000'000 ? 2 : 1;
    // a margin, for scanned film whose scan pixels map a little outside the nominal frame
    mMargin = mStep * static_cast<int>( std::ceil( ( 8 + 0.03 * std::max( camera.width, camera.height ) ) / mStep ) );
    mNodesX = ( camera.width + 2 * mMargin + mStep - 1 ) / mStep + 1;
    mNodesY = ( camera.height + 2 * mMargin + mStep - 1 ) / mStep + 1;
    mRays.resize( static_cast<size_t>( mNodesX ) * mNodesY );
    mValid.assign( mRays.size(), 0 );
    for ( int j = 0; j < mNodesY; ++j )
      for ( int i = 0; i < mNodesX; ++i )
        if ( const std::optional<Eigen::Vector3d> ray = camera.rayInCameraFromPixel( Eigen::Vector2d( i * mStep - mMargin, j * mStep - mMargin ) ) )
        {
          // scaled to z = -1, so that interpolating them interpolates the ideal image plane
          mRays[static_cast<size_t>( j ) * mNodesX + i] = ( *ray / -ray->z() ).cast<float>();
          mValid[static_cast<size_t>( j ) * mNodesX + i] = 1;
        }
  }

  bool CameraRays::rayAt( double col, double row, Eigen::Vector3d &rayInCamera ) const
  {
    const double gx = std::clamp( ( col + mMargin ) / mStep, 0.0, mNodesX - 1.0 ), gy = std::clamp( ( row + mMargin ) / mStep, 0.0, mNodesY - 1.0 );
    const int i = std::min( static_cast<int>( gx ), mNodesX - 2 ), j = std::min( static_cast<int>( gy ), mNodesY - 2 );
    const size_t k = static_cast<size_t>( j ) * mNodesX + i;
    if ( !mValid[k] || !mValid[k + 1] || !mValid[k + mNodesX] || !mValid[k + mNodesX + 1] )
      return false;
    const double u = gx - i, v = gy - j;
    rayInCamera = ( ( 1 - u ) * ( 1 - v ) * mRays[k].cast<double>() + u * ( 1 - v ) * mRays[k + 1].cast<double>()
                    + ( 1 - u ) * v * mRays[k + mNodesX].cast<double>() + u * v * mRays[k + mNodesX + 1].cast<double>() );
    return true;
  }

  cv::Mat renderImage( const Scene &scene, const OrientedImage &image, const CameraRays *rays, const RenderOptions &options,
                       RenderSummary *summary )
  {
    const Camera &camera = image.camera();
    std::unique_ptr<CameraRays> ownRays;
    if ( !rays )
    {
      ownRays = std::make_unique<CameraRays>( camera );
      rays = ownRays.get();
    }
    const int width = camera.width, height = camera.height;
    const Eigen::Matrix3d worldFromCamera = image.exterior().worldFromCamera();
    const Eigen::Vector3d origin = image.exterior().projectionCentre;
    const double pixelAngle = 1.0 / camera.f;
    const int nBase = std::max( 1, options.supersampling );

    cv::Mat rgb( height, width, CV_32FC3, cv::Scalar( 0, 0, 0 ) );
    std::vector<uint32_t> keys( static_cast<size_t>( width ) * height, 0xFFFFFFFFu );
    std::atomic<long> sky { 0 }, supersampled { 0 }, rayCount { 0 };
    const int threads = std::max( 1, options.threads );
    constexpr int kRowsPerChunk = 8;

    const auto runParallel = [&]( auto &&rowJob )
    {
      std::atomic<int> nextChunk { 0 };
      const auto worker = [&]()
      {
        for ( int chunk; ( chunk = nextChunk.fetch_add( 1 ) ) * kRowsPerChunk < height; )
          for ( int row = chunk * kRowsPerChunk; row < std::min( height, ( chunk + 1 ) * kRowsPerChunk ); ++row )
            rowJob( row );
      };
      std::vector<std::thread> pool;
      for ( int k = 1; k < threads; ++k )
        pool.emplace_back( worker );
      worker();
      for ( std::thread &t : pool )
        t.join();
    };

    // Pass 1: one ray per pixel centre.
    runParallel( [&]( int row )
    {
      long localSky = 0;
      cv::Vec3f *out = rgb.ptr<cv::Vec3f>( row );
      for ( int col = 0; col < width; ++col )
      {
        Eigen::Vector3d ray;
        const Eigen::Vector2d nominal = image.nominalFromScan( Eigen::Vector2d( col + 0.5, row + 0.5 ) );
        if ( !rays->rayAt( nominal.x(), nominal.y(), ray ) )
          continue;
        const Eigen::Vector3d direction = worldFromCamera * ray;
        const SurfaceSample sample = scene.trace( origin, direction.normalized(), pixelAngle );
        out[col] = cv::Vec3f( sample.rgb.x(), sample.rgb.y(), sample.rgb.z() );
        keys[static_cast<size_t>( row ) * width + col] = sample.key;
        localSky += sample.sky ? 1 : 0;
      }
      sky += localSky;
      rayCount += width;
    } );

    // Pass 2: supersample the pixels on an edge between surfaces.
    if ( nBase > 1 )
    {
      runParallel( [&]( int row )
      {
        long localRays = 0, localPixels = 0;
        cv::Vec3f *out = rgb.ptr<cv::Vec3f>( row );
        for ( int col = 0; col < width; ++col )
        {
          const uint32_t key = keys[static_cast<size_t>( row ) * width + col];
          bool edge = !options.adaptive, mark = Scene::isControlTargetKey( key );
          for ( int dr = -1; dr <= 1; ++dr )
            for ( int dc = -1; dc <= 1; ++dc )
            {
              const int r = row + dr, c = col + dc;
              if ( r < 0 || c < 0 || r >= height || c >= width || keys[static_cast<size_t>( r ) * width + c] == key )
                continue;
              const bool otherMark = Scene::isControlTargetKey( keys[static_cast<size_t>( r ) * width + c] );
              // diagonal neighbours count only around control targets, which must be covered completely
              if ( dr != 0 && dc != 0 && !otherMark && !Scene::isControlTargetKey( key ) )
                continue;
              edge = true;
              mark = mark || otherMark;
            }
          if ( !edge )
            continue;
          // control targets are measured to hundredths of a pixel: sample their edges finer
          const int n = mark ? 4 * nBase : nBase;
          Eigen::Vector3f sum = Eigen::Vector3f::Zero();
          int count = 0;
          for ( int sj = 0; sj < n; ++sj )
            for ( int si = 0; si < n; ++si )
            {
              Eigen::Vector3d ray;
              const Eigen::Vector2d nominal = image.nominalFromScan( Eigen::Vector2d( col + ( si + 0.5 ) / n, row + ( sj + 0.5 ) / n ) );
              if ( !rays->rayAt( nominal.x(), nominal.y(), ray ) )
                continue;
              const SurfaceSample sample = scene.trace( origin, ( worldFromCamera * ray ).normalized(), pixelAngle / n );
              sum += sample.rgb;
              ++count;
            }
          localRays += n * n;
          ++localPixels;
          if ( count > 0 )
          {
            sum /= static_cast<float>( count );
            out[col] = cv::Vec3f( sum.x(), sum.y(), sum.z() );
          }
        }
        rayCount += localRays;
        supersampled += localPixels;
      } );
    }
    if ( summary )
    {
      summary->rays += rayCount;
      summary->supersampledPixels += supersampled;
      summary->skyPixels += sky;
      summary->pixels += static_cast<long>( width ) * height;
    }
    return rgb;
  }

} // namespace geostation
