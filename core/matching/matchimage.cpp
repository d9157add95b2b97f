/***************************************************************************
  matchimage.cpp - grey conversion and gradients for matching
 ***************************************************************************/
#include "matching/matchimage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include <opencv2/imgproc.hpp>

#include "io/rasterfile.h"

namespace geostation
{

  MatchImage::MatchImage( const cv::Mat &image )
  {
    prepare( image );
    mImageSize = mGrey.size();
    mOffered = cv::Rect( 0, 0, mImageSize.width, mImageSize.height );
  }

  MatchImage::MatchImage( const cv::Mat &window, const cv::Point &origin, const cv::Size &imageSize, const std::optional<std::pair<double, double>> &range )
  {
    const cv::Rect held( origin, window.size() );
    if ( window.empty() || ( held & cv::Rect( 0, 0, imageSize.width, imageSize.height ) ) != held )
      throw std::invalid_argument( "the window does not lie in the image" );
    prepare( window, range );
    mOrigin = origin;
    mImageSize = imageSize;
    // the inner edges' margins are held, not offered; the image's own edges are offered as in a whole image
    const int m = kWindowMarginPx;
    const int left = held.x > 0 ? held.x + m : 0, top = held.y > 0 ? held.y + m : 0;
    const int right = held.br().x < imageSize.width ? held.br().x - m : imageSize.width;
    const int bottom = held.br().y < imageSize.height ? held.br().y - m : imageSize.height;
    mOffered = cv::Rect( left, top, std::max( 0, right - left ), std::max( 0, bottom - top ) );
  }

  cv::Mat matchingGrey( const cv::Mat &image )
  {
    if ( image.empty() )
      throw std::invalid_argument( "the image is empty" );
    if ( image.depth() != CV_8U && image.depth() != CV_16U )
      throw std::invalid_argument( "matching needs an 8- or 16-bit image" );
    cv::Mat grey;
    switch ( image.channels() )
    {
      case 1:
        grey = image;
        break;
      case 3:
        cv::cvtColor( image, grey, cv::COLOR_RGB2GRAY );
        break;
      case 4:
        cv::cvtColor( image, grey, cv::COLOR_RGBA2GRAY );
        break;
      default:
        throw std::invalid_argument( "matching needs a grey, RGB or RGBA image" );
    }
    return grey;
  }

  std::pair<double, double> greyRangeOf( const RasterReader &reader )
  {
    const cv::Size size = reader.size();
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    constexpr int kStripRows = 256;
    for ( int row = 0; row < size.height; row += kStripRows )
    {
      double a = 0, b = 0;
      cv::minMaxLoc( matchingGrey( reader.read( cv::Rect( 0, row, size.width, std::min( kStripRows, size.height - row ) ) ).pixels ), &a, &b );
      lo = std::min( lo, a );
      hi = std::max( hi, b );
    }
    return { lo, hi };
  }

  cv::Mat matchingValues( const cv::Mat &image, const std::optional<std::pair<double, double>> &range )
  {
    const cv::Mat grey = matchingGrey( image );
    cv::Mat values;
    if ( grey.depth() == CV_8U )
      grey.convertTo( values, CV_32F );
    else
    {
      double lo = 0, hi = 0;
      if ( range )
        std::tie( lo, hi ) = *range;
      else
        cv::minMaxLoc( grey, &lo, &hi );
      const double scale = hi > lo ? 255.0 / ( hi - lo ) : 1.0;
      grey.convertTo( values, CV_32F, scale, -lo * scale );
    }
    return values;
  }

  cv::Rect matchingWindowToRead( const cv::Rect &offered, const cv::Size &imageSize )
  {
    const int m = MatchImage::kWindowMarginPx;
    return cv::Rect( offered.x - m, offered.y - m, offered.width + 2 * m, offered.height + 2 * m ) & cv::Rect( 0, 0, imageSize.width, imageSize.height );
  }

  void MatchImage::prepare( const cv::Mat &image, const std::optional<std::pair<double, double>> &range )
  {
    mValue = matchingValues( image, range );
    if ( mValue.cols < 3 || mValue.rows < 3 )
      throw std::invalid_argument( "the image is smaller than 3 x 3 pixels" );
    mValue.convertTo( mGrey, CV_8U ); // rounds
    // cubic B-spline coefficients (Unser's recursive prefilter, mirror boundaries), so that
    // sampleCubic() interpolates the pixel values exactly with the spline's flat frequency response
    mCoefficients = mValue.clone();
    const double z = std::sqrt( 3.0 ) - 2.0, lambda = ( 1 - z ) * ( 1 - 1 / z );
    const auto prefilter = [&]( float *c, int n, int stride )
    {
      if ( n < 2 )
        return;
      for ( int k = 0; k < n; ++k )
        c[k * stride] = static_cast<float>( c[k * stride] * lambda );
      // causal initialisation (mirror), truncated sum
      double sum = c[0], zk = z;
      const int horizon = std::min( n, 24 );
      for ( int k = 1; k < horizon; ++k, zk *= z )
        sum += zk * c[k * stride];
      c[0] = static_cast<float>( sum );
      for ( int k = 1; k < n; ++k )
        c[k * stride] = static_cast<float>( c[k * stride] + z * c[( k - 1 ) * stride] );
      c[( n - 1 ) * stride] = static_cast<float>( ( z / ( z * z - 1 ) ) * ( z * c[( n - 2 ) * stride] + c[( n - 1 ) * stride] ) );
      for ( int k = n - 2; k >= 0; --k )
        c[k * stride] = static_cast<float>( z * ( c[( k + 1 ) * stride] - c[k * stride] ) );
    };
    for ( int r = 0; r < mCoefficients.rows; ++r )
      prefilter( mCoefficients.ptr<float>( r ), mCoefficients.cols, 1 );
    for ( int c = 0; c < mCoefficients.cols; ++c )
      prefilter( mCoefficients.ptr<float>( 0 ) + c, mCoefficients.rows, static_cast<int>( mCoefficients.step1() ) );
  }

  namespace
  {
    //! Cubic B-spline weights and their derivatives for fractional offset t in [0, 1).
    void bspline( float t, float w[4], float d[4] )
    {
      const float t2 = t * t, t3 = t2 * t, u = 1.0f - t;
      w[0] = u * u * u / 6.0f;
      w[1] = ( 3.0f * t3 - 6.0f * t2 + 4.0f ) / 6.0f;
      w[2] = ( -3.0f * t3 + 3.0f * t2 + 3.0f * t + 1.0f ) / 6.0f;
      w[3] = t3 / 6.0f;
      d[0] = -0.5f * u * u;
      d[1] = 1.5f * t2 - 2.0f * t;
      d[2] = -1.5f * t2 + t + 0.5f;
      d[3] = 0.5f * t2;
    }
  }

  float MatchImage::sampleBilinear( double col, double row, float *dCol, float *dRow ) const
  {
    const auto at = [this]( double c, double r )
    {
      const double x = c - 0.5 - mOrigin.x, y = r - 0.5 - mOrigin.y;
      const int i = static_cast<int>( std::floor( x ) ), j = static_cast<int>( std::floor( y ) );
      const float fx = static_cast<float>( x - i ), fy = static_cast<float>( y - j );
      const float *top = mValue.ptr<float>( j ) + i, *bottom = mValue.ptr<float>( j + 1 ) + i;
      return ( 1 - fy ) * ( ( 1 - fx ) * top[0] + fx * top[1] ) + fy * ( ( 1 - fx ) * bottom[0] + fx * bottom[1] );
    };
    if ( dCol )
      *dCol = at( col + 0.5, row ) - at( col - 0.5, row );
    if ( dRow )
      *dRow = at( col, row + 0.5 ) - at( col, row - 0.5 );
    return at( col, row );
  }

  float MatchImage::sampleCubic( double col, double row, float *dCol, float *dRow ) const
  {
    const double x = col - 0.5 - mOrigin.x, y = row - 0.5 - mOrigin.y;
    const int i = static_cast<int>( std::floor( x ) ), j = static_cast<int>( std::floor( y ) );
    float wx[4], dx[4], wy[4], dy[4];
    bspline( static_cast<float>( x - i ), wx, dx );
    bspline( static_cast<float>( y - j ), wy, dy );
    float value = 0, gx = 0, gy = 0;
    for ( int m = 0; m < 4; ++m )
    {
      const float *line = mCoefficients.ptr<float>( j - 1 + m ) + ( i - 1 );
      float rowValue = 0, rowDerivative = 0;
      for ( int k = 0; k < 4; ++k )
      {
        rowValue += wx[k] * line[k];
        rowDerivative += dx[k] * line[k];
      }
      value += wy[m] * rowValue;
      gx += wy[m] * rowDerivative;
      gy += dy[m] * rowValue;
    }
    if ( dCol )
      *dCol = gx;
    if ( dRow )
      *dRow = gy;
    return value;
  }

} // namespace geostation
