/***************************************************************************
  matchimage.cpp - grey conversion and gradients for matching
 ***************************************************************************/
#include "matching/matchimage.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace geostation
{

  MatchImage::MatchImage( const cv::Mat &image )
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
    if ( grey.cols < 3 || grey.rows < 3 )
      throw std::invalid_argument( "the image is smaller than 3 x 3 pixels" );
    if ( grey.depth() == CV_8U )
      grey.convertTo( mValue, CV_32F );
    else
    {
      double lo = 0, hi = 0;
      cv::minMaxLoc( grey, &lo, &hi );
      const double scale = hi > lo ? 255.0 / ( hi - lo ) : 1.0;
      grey.convertTo( mValue, CV_32F, scale, -lo * scale );
    }
    mValue.convertTo( mGrey, CV_8U ); // rounds
    mGradX = cv::Mat::zeros( mValue.size(), CV_32F );
    mGradY = cv::Mat::zeros( mValue.size(), CV_32F );
    for ( int r = 0; r < mValue.rows; ++r )
    {
      const float *row = mValue.ptr<float>( r );
      const float *up = mValue.ptr<float>( std::max( 0, r - 1 ) ), *down = mValue.ptr<float>( std::min( mValue.rows - 1, r + 1 ) );
      float *gx = mGradX.ptr<float>( r ), *gy = mGradY.ptr<float>( r );
      const float yScale = ( r == 0 || r == mValue.rows - 1 ) ? 1.0f : 0.5f;
      for ( int c = 0; c < mValue.cols; ++c )
      {
        const int left = std::max( 0, c - 1 ), right = std::min( mValue.cols - 1, c + 1 );
        gx[c] = ( row[right] - row[left] ) / static_cast<float>( right - left );
        gy[c] = ( down[c] - up[c] ) * yScale;
      }
    }
  }

  namespace
  {
    //! Keys' cubic convolution weights (a = -0.5) and their derivatives for fractional offset t in [0, 1).
    void keys( float t, float w[4], float d[4] )
    {
      const float t2 = t * t, t3 = t2 * t;
      w[0] = -0.5f * t3 + t2 - 0.5f * t;
      w[1] = 1.5f * t3 - 2.5f * t2 + 1.0f;
      w[2] = -1.5f * t3 + 2.0f * t2 + 0.5f * t;
      w[3] = 0.5f * t3 - 0.5f * t2;
      d[0] = -1.5f * t2 + 2.0f * t - 0.5f;
      d[1] = 4.5f * t2 - 5.0f * t;
      d[2] = -4.5f * t2 + 4.0f * t + 0.5f;
      d[3] = 1.5f * t2 - t;
    }
  }

  float MatchImage::sampleCubic( double col, double row, float *dCol, float *dRow ) const
  {
    const double x = col - 0.5, y = row - 0.5;
    const int i = static_cast<int>( std::floor( x ) ), j = static_cast<int>( std::floor( y ) );
    float wx[4], dx[4], wy[4], dy[4];
    keys( static_cast<float>( x - i ), wx, dx );
    keys( static_cast<float>( y - j ), wy, dy );
    float value = 0, gx = 0, gy = 0;
    for ( int m = 0; m < 4; ++m )
    {
      const float *line = mValue.ptr<float>( j - 1 + m ) + ( i - 1 );
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
