/***************************************************************************
  orthophotopair.h - a vertical stereo pair (or a strip of them) resampled
  from a real orthophoto, for tests on real imagery at a known ground pixel
  -------------------------------------------------------------------------
  A real grey orthophoto (north up, square ground pixels of `gsdM`) is laid
  on level ground at `groundM`; two vertical photos of one camera model
  (the orthophoto's size, principal distance = its width) look at it from
  `groundM + f * gsdM`, the second displaced north by a fraction of the
  footprint and both tilted a little, so neither is the orthophoto itself
  (a strip: each photo displaced so from the one before).
  Each photo pixel is the orthophoto's grey where its ray meets the ground
  (bicubic), blurred by 0.5 px and given noise of 2 grey levels; pixels
  whose ray falls beyond the orthophoto are 0.

  Ground x east, y north, metres from the orthophoto's centre; truth
  digitised on the orthophoto (pixelInImage, centres at i + 0.5) is
  carried into a photo by the collinearity equations (orthoToGround, then
  projectGroundToPixel).
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_ORTHOPHOTOPAIR_H
#define GEOSTATION_TESTS_ORTHOPHOTOPAIR_H

#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "camera/camera.h"
#include "geometry/projection.h"
#include "imagelinescoring.h"

namespace geostation::orthophotopair
{
  //! The photos over an orthophoto: a pair, or a strip of them (orthophotoStrip()).
  struct OrthophotoPair
  {
    Camera camera;
    std::vector<ExteriorOrientation> exterior; //!< A, B (a strip: each photo in order)
    std::vector<cv::Mat> grey;                 //!< the same photos' grey levels
    cv::Size ortho;
    double gsdM = 1.0;
    double groundM = 200.0;

    //! Ground (x, y, groundM) of an orthophoto pixelInImage position.
    Eigen::Vector3d orthoToGround( const Eigen::Vector2d &p ) const
    {
      return Eigen::Vector3d( ( p.x() - 0.5 * ortho.width ) * gsdM, ( 0.5 * ortho.height - p.y() ) * gsdM, groundM );
    }
    //! The orthophoto pixelInImage position of a ground point.
    Eigen::Vector2d groundToOrtho( const Eigen::Vector3d &g ) const { return Eigen::Vector2d( g.x() / gsdM + 0.5 * ortho.width, 0.5 * ortho.height - g.y() / gsdM ); }
    OrientedImage photo( int k ) const { return OrientedImage( camera, exterior[static_cast<size_t>( k )] ); }
    //! Where the ray of photo k's pixel meets the ground.
    Eigen::Vector3d groundSeen( const OrientedImage &image, const Eigen::Vector2d &pixelInImage ) const
    {
      const std::optional<Ray> ray = image.worldRayFromPixel( pixelInImage );
      return ray->origin + ( groundM - ray->origin.z() ) / ray->direction.z() * ray->direction;
    }
    //! Whether both photos of the pair (photos `first` and `first` + 1 of a strip) see the ground point more than `marginPx` inside their frames.
    bool bothSee( const Eigen::Vector3d &g, double marginPx, int first = 0 ) const
    {
      for ( int k = first; k < first + 2; ++k )
      {
        const GroundProjection q = photo( k ).projectGroundToPixel( g );
        if ( !q.ok() || q.pixelInImage.x() <= marginPx || q.pixelInImage.y() <= marginPx || q.pixelInImage.x() >= camera.width - marginPx ||
             q.pixelInImage.y() >= camera.height - marginPx )
          return false;
      }
      return true;
    }
  };

  /**
   * A strip of `photos` vertical photos over `ortho` (8-bit grey), photo k
   * displaced north by k x `baseFraction` of the footprint's height
   * (negative: south), tilted a little, alternately one way and the
   * other; consecutive photos are the strip's pairs.
   */
  inline OrthophotoPair orthophotoStrip( const cv::Mat &ortho, double gsdM, double baseFraction, int photos, uint32_t seed = 11 )
  {
    OrthophotoPair pair;
    pair.ortho = ortho.size();
    pair.gsdM = gsdM;
    Camera &camera = pair.camera;
    camera.id = "one";
    camera.width = ortho.cols;
    camera.height = ortho.rows;
    camera.f = ortho.cols;
    camera.cx = ortho.cols / 2.0;
    camera.cy = ortho.rows / 2.0;
    camera.pixelSizeMm = 0.006;
    const double flyingM = pair.groundM + camera.f * gsdM;
    for ( int k = 0; k < photos; ++k )
    {
      ExteriorOrientation e;
      e.projectionCentre = Eigen::Vector3d( 0.0, k * baseFraction * ortho.rows * gsdM, flyingM );
      e.omegaDeg = k % 2 == 0 ? 0.2 : -0.3;
      e.phiDeg = k % 2 == 0 ? -0.15 : 0.25;
      e.kappaDeg = k % 2 == 0 ? 0.3 : -0.5;
      pair.exterior.push_back( e );
    }
    std::mt19937 random( seed );
    std::normal_distribution<double> noise( 0.0, 2.0 );
    for ( int k = 0; k < photos; ++k )
    {
      const OrientedImage image = pair.photo( k );
      cv::Mat mapX( camera.height, camera.width, CV_32F ), mapY( camera.height, camera.width, CV_32F );
      for ( int r = 0; r < camera.height; ++r )
        for ( int c = 0; c < camera.width; ++c )
        {
          // the orthophoto's pixel indices (OpenCV: centres at i)
          const Eigen::Vector2d at = pair.groundToOrtho( pair.groundSeen( image, Eigen::Vector2d( c + 0.5, r + 0.5 ) ) ) - Eigen::Vector2d( 0.5, 0.5 );
          mapX.at<float>( r, c ) = static_cast<float>( at.x() );
          mapY.at<float>( r, c ) = static_cast<float>( at.y() );
        }
      cv::Mat sampled;
      cv::remap( ortho, sampled, mapX, mapY, cv::INTER_CUBIC, cv::BORDER_CONSTANT, cv::Scalar( 0 ) );
      cv::Mat blurred;
      sampled.convertTo( blurred, CV_32F );
      cv::GaussianBlur( blurred, blurred, cv::Size( 0, 0 ), 0.5 );
      cv::Mat grey( camera.height, camera.width, CV_8U );
      for ( int r = 0; r < camera.height; ++r )
        for ( int c = 0; c < camera.width; ++c )
          grey.at<uint8_t>( r, c ) = sampled.at<uint8_t>( r, c ) == 0 ? 0 : cv::saturate_cast<uint8_t>( blurred.at<float>( r, c ) + noise( random ) );
      pair.grey.push_back( grey );
    }
    return pair;
  }

  /**
   * The pair over `ortho` (8-bit grey). `baseFraction`: the second photo's
   * displacement north as a fraction of the footprint's height (negative:
   * south).
   */
  inline OrthophotoPair orthophotoPair( const cv::Mat &ortho, double gsdM, double baseFraction = 0.3, uint32_t seed = 11 )
  {
    return orthophotoStrip( ortho, gsdM, baseFraction, 2, seed );
  }

  /**
   * Lines digitised on the orthophoto carried into photo k, sampled every
   * pixel and cut to the parts both photos see (`marginPx` from their edges).
   */
  inline std::vector<PixelPolyline> inPhoto( const OrthophotoPair &pair, int k, const std::vector<PixelPolyline> &orthoLines, double marginPx )
  {
    const OrientedImage self = pair.photo( k );
    std::vector<PixelPolyline> out;
    for ( const PixelPolyline &line : orthoLines )
    {
      PixelPolyline current;
      for ( size_t i = 0; i + 1 < line.size(); ++i )
      {
        const int n = std::max( 1, static_cast<int>( ( line[i + 1] - line[i] ).norm() ) );
        for ( int s = 0; s <= n; ++s )
        {
          if ( s == n && i + 2 < line.size() )
            break; // the next segment starts here
          const Eigen::Vector3d g = pair.orthoToGround( line[i] + ( line[i + 1] - line[i] ) * s / n );
          if ( pair.bothSee( g, marginPx ) )
            current.push_back( self.projectGroundToPixel( g ).pixelInImage );
          else
          {
            if ( current.size() > 1 )
              out.push_back( current );
            current.clear();
          }
        }
      }
      if ( current.size() > 1 )
        out.push_back( current );
    }
    return out;
  }
} // namespace geostation::orthophotopair

#endif // GEOSTATION_TESTS_ORTHOPHOTOPAIR_H
