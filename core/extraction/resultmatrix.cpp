/***************************************************************************
  resultmatrix.cpp - the raster record of what was extracted
 ***************************************************************************/
#include "extraction/resultmatrix.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace geostation
{

  ResultMatrix::ResultMatrix( int width, int height )
  {
    if ( width <= 0 || height <= 0 )
      throw std::invalid_argument( "a result matrix needs a positive size" );
    mSymbols = cv::Mat::zeros( height, width, CV_8UC1 );
  }

  ResultMatrix ResultMatrix::view( const cv::Rect &rect, const cv::Point &origin ) const
  {
    ResultMatrix part;
    const cv::Rect clipped = rect & cv::Rect( mShift, mSymbols.size() );
    if ( !clipped.empty() )
      part.mSymbols = mSymbols( clipped - mShift );
    part.mShift = clipped.tl() - origin;
    return part;
  }

  uint8_t ResultMatrix::at( int col, int row ) const
  {
    col -= mShift.x;
    row -= mShift.y;
    if ( col < 0 || row < 0 || col >= mSymbols.cols || row >= mSymbols.rows )
      return 0;
    return mSymbols.at<uint8_t>( row, col );
  }

  void ResultMatrix::drawPolyline( const std::vector<Eigen::Vector2d> &pixelsInImage, uint8_t symbol, bool overwrite )
  {
    if ( pixelsInImage.empty() )
      return;
    const auto cell = [this]( const Eigen::Vector2d &p ) { return cv::Point( static_cast<int>( std::floor( p.x() ) ), static_cast<int>( std::floor( p.y() ) ) ) - mShift; };
    const auto put = [&]( const cv::Point &c )
    {
      if ( c.x < 0 || c.y < 0 || c.x >= mSymbols.cols || c.y >= mSymbols.rows )
        return;
      uint8_t &v = mSymbols.at<uint8_t>( c.y, c.x );
      if ( overwrite || v == 0 )
        v = symbol;
    };
    put( cell( pixelsInImage.front() ) );
    for ( size_t i = 1; i < pixelsInImage.size(); ++i )
    {
      const cv::Point a = cell( pixelsInImage[i - 1] ), b = cell( pixelsInImage[i] );
      // Bresenham through the big canvas: LineIterator clips to the matrix
      cv::LineIterator it( mSymbols, a, b, 8 );
      for ( int k = 0; k < it.count; ++k, ++it )
        put( it.pos() );
    }
  }

  std::optional<Eigen::Vector2i> ResultMatrix::nearestSymbol( const Eigen::Vector2d &pixelInView, double radiusPx, const std::string &symbols ) const
  {
    const Eigen::Vector2d pixelInImage = pixelInView - Eigen::Vector2d( mShift.x, mShift.y ); // in the pixels held
    const int r = static_cast<int>( std::ceil( radiusPx ) );
    const int cc = static_cast<int>( std::floor( pixelInImage.x() ) ), rc = static_cast<int>( std::floor( pixelInImage.y() ) );
    std::optional<Eigen::Vector2i> best;
    double bestD2 = radiusPx * radiusPx;
    for ( int row = std::max( 0, rc - r ); row <= std::min( mSymbols.rows - 1, rc + r ); ++row )
    {
      const uint8_t *line = mSymbols.ptr<uint8_t>( row );
      for ( int col = std::max( 0, cc - r ); col <= std::min( mSymbols.cols - 1, cc + r ); ++col )
      {
        const uint8_t v = line[col];
        if ( v == 0 || ( !symbols.empty() && symbols.find( static_cast<char>( v ) ) == std::string::npos ) )
          continue;
        const double d2 = ( col + 0.5 - pixelInImage.x() ) * ( col + 0.5 - pixelInImage.x() ) + ( row + 0.5 - pixelInImage.y() ) * ( row + 0.5 - pixelInImage.y() );
        if ( d2 <= bestD2 )
        {
          bestD2 = d2;
          best = Eigen::Vector2i( col, row );
        }
      }
    }
    if ( best )
      *best += Eigen::Vector2i( mShift.x, mShift.y );
    return best;
  }

  void ResultMatrix::erase( const std::string &symbols )
  {
    for ( int row = 0; row < mSymbols.rows; ++row )
    {
      uint8_t *line = mSymbols.ptr<uint8_t>( row );
      for ( int col = 0; col < mSymbols.cols; ++col )
        if ( line[col] && symbols.find( static_cast<char>( line[col] ) ) != std::string::npos )
          line[col] = 0;
    }
  }

  long ResultMatrix::count( const std::string &symbols ) const
  {
    long n = 0;
    for ( int row = 0; row < mSymbols.rows; ++row )
    {
      const uint8_t *line = mSymbols.ptr<uint8_t>( row );
      for ( int col = 0; col < mSymbols.cols; ++col )
        n += line[col] && symbols.find( static_cast<char>( line[col] ) ) != std::string::npos;
    }
    return n;
  }

  double polylineLength( const std::vector<Eigen::Vector2d> &polyline )
  {
    double length = 0.0;
    for ( size_t i = 1; i < polyline.size(); ++i )
      length += ( polyline[i] - polyline[i - 1] ).norm();
    return length;
  }

} // namespace geostation
