/***************************************************************************
  degradation.cpp - exposure, vignetting, blur, noise, bit errors, JPEG
 ***************************************************************************/
#include "simulation/degradation.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace geostation
{

  void DegradationOptions::validate() const
  {
    const auto require = []( bool ok, const std::string &what )
    {
      if ( !ok )
        throw std::invalid_argument( what );
    };
    require( exposure > 0.0 && exposure <= 20.0, "exposure must be a gain between 0 and 20" );
    require( vignetting >= 0.0 && vignetting <= 1.0, "vignetting must be between 0 and 1" );
    require( blurSigmaPx >= 0.0 && blurSigmaPx <= 50.0, "blur must be between 0 and 50 pixels" );
    require( noiseSigma >= 0.0 && noiseSigma <= 128.0, "noise must be between 0 and 128 grey levels" );
    require( bitErrorRate >= 0.0 && bitErrorRate <= 0.5, "the bit-error rate must be between 0 and 0.5" );
    require( jpegQuality >= 0 && jpegQuality <= 100, "the JPEG quality must be between 1 and 100 (0 = off)" );
  }

  cv::Mat degradeAndQuantise( const cv::Mat &linearRgb, const DegradationOptions &options, uint32_t seed )
  {
    options.validate();
    cv::Mat image = linearRgb * ( 255.0 * options.exposure );
    if ( options.vignetting > 0.0 )
    {
      // cos^4-like fall-off: 1 at the centre, 1 - vignetting at the corners
      const double cx = 0.5 * image.cols, cy = 0.5 * image.rows, r2max = cx * cx + cy * cy;
      for ( int row = 0; row < image.rows; ++row )
      {
        cv::Vec3f *p = image.ptr<cv::Vec3f>( row );
        for ( int col = 0; col < image.cols; ++col )
        {
          const double r2 = ( ( col + 0.5 - cx ) * ( col + 0.5 - cx ) + ( row + 0.5 - cy ) * ( row + 0.5 - cy ) ) / r2max;
          p[col] *= static_cast<float>( 1.0 - options.vignetting * r2 * ( 2.0 - r2 ) );
        }
      }
    }
    if ( options.blurSigmaPx > 0.0 )
      cv::GaussianBlur( image, image, cv::Size( 0, 0 ), options.blurSigmaPx, options.blurSigmaPx, cv::BORDER_REFLECT );
    std::mt19937 random( seed );
    if ( options.noiseSigma > 0.0 )
    {
      std::normal_distribution<float> gauss( 0.0f, static_cast<float>( options.noiseSigma ) );
      for ( int row = 0; row < image.rows; ++row )
      {
        cv::Vec3f *p = image.ptr<cv::Vec3f>( row );
        for ( int col = 0; col < image.cols; ++col )
          for ( int k = 0; k < 3; ++k )
            p[col][k] += gauss( random );
      }
    }
    cv::Mat out;
    image.convertTo( out, CV_8UC3 ); // rounds and saturates
    if ( options.bitErrorRate > 0.0 )
    {
      std::uniform_real_distribution<double> uniform( 0.0, 1.0 );
      for ( int row = 0; row < out.rows; ++row )
      {
        cv::Vec3b *p = out.ptr<cv::Vec3b>( row );
        for ( int col = 0; col < out.cols; ++col )
          if ( uniform( random ) < options.bitErrorRate )
          {
            const uchar v = uniform( random ) < 0.5 ? 0 : 255;
            p[col] = cv::Vec3b( v, v, v );
          }
      }
    }
    if ( options.jpegQuality > 0 )
    {
      std::vector<uchar> buffer;
      cv::Mat bgr;
      cv::cvtColor( out, bgr, cv::COLOR_RGB2BGR );
      cv::imencode( ".jpg", bgr, buffer, { cv::IMWRITE_JPEG_QUALITY, options.jpegQuality } );
      cv::cvtColor( cv::imdecode( buffer, cv::IMREAD_COLOR ), out, cv::COLOR_BGR2RGB );
    }
    return out;
  }

} // namespace geostation
