/***************************************************************************
  edgeprimitives.cpp - gradients, line filter, thinning, Förstner, COG, DP
 ***************************************************************************/
#include "imageproc/edgeprimitives.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <Eigen/Dense>

namespace geostation
{
  namespace
  {
    // Figure 6.5: 0 1 2 / 7 . 3 / 6 5 4
    constexpr int kRow[8] = { -1, -1, -1, 0, 1, 1, 1, 0 };
    constexpr int kCol[8] = { -1, 0, 1, 1, 1, 0, -1, -1 };

    void requireGrey( const cv::Mat &grey )
    {
      if ( grey.empty() || grey.type() != CV_8UC1 )
        throw std::invalid_argument( "edge primitives need an 8-bit single-band image" );
    }

    std::array<std::array<uint8_t, 256>, 2> makeTables()
    {
      std::array<std::array<uint8_t, 256>, 2> tables {};
      for ( int code = 0; code < 256; ++code )
      {
        const auto bit = [&]( int i ) { return ( code >> i ) & 1; };
        // Zhang-Suen's P2..P9: N, NE, E, SE, S, SW, W, NW
        const int p2 = bit( 1 ), p3 = bit( 2 ), p4 = bit( 3 ), p5 = bit( 4 ), p6 = bit( 5 ), p7 = bit( 6 ), p8 = bit( 7 ), p9 = bit( 0 );
        const int sequence[9] = { p2, p3, p4, p5, p6, p7, p8, p9, p2 };
        int neighbours = 0, transitions = 0;
        for ( int i = 0; i < 8; ++i )
        {
          neighbours += sequence[i];
          transitions += ( sequence[i] == 0 && sequence[i + 1] == 1 ) ? 1 : 0;
        }
        if ( neighbours == 0 )
        {
          tables[0][code] = tables[1][code] = 1; // an isolated pixel: a bit error
          continue;
        }
        if ( neighbours < 2 || neighbours > 6 || transitions != 1 )
          continue; // a line end, an interior pixel, or a pixel that holds parts together
        tables[0][code] = ( p2 * p4 * p6 == 0 && p4 * p6 * p8 == 0 ) ? 1 : 0;
        tables[1][code] = ( p2 * p4 * p8 == 0 && p2 * p6 * p8 == 0 ) ? 1 : 0;
      }
      return tables;
    }
  }

  cv::Mat gradientMagnitude( const cv::Mat &grey, GradientFilter filter )
  {
    requireGrey( grey );
    cv::Mat out( grey.size(), CV_32F, cv::Scalar( 0 ) );
    const auto at = [&]( int r, int c ) { return static_cast<float>( grey.at<uint8_t>( std::clamp( r, 0, grey.rows - 1 ), std::clamp( c, 0, grey.cols - 1 ) ) ); };
    for ( int r = 0; r < grey.rows; ++r )
      for ( int c = 0; c < grey.cols; ++c )
      {
        const float gx = ( at( r + 1, c - 1 ) + 2 * at( r + 1, c ) + at( r + 1, c + 1 ) ) - ( at( r - 1, c - 1 ) + 2 * at( r - 1, c ) + at( r - 1, c + 1 ) );
        const float gy = ( at( r - 1, c + 1 ) + 2 * at( r, c + 1 ) + at( r + 1, c + 1 ) ) - ( at( r - 1, c - 1 ) + 2 * at( r, c - 1 ) + at( r + 1, c - 1 ) );
        float g = std::max( std::abs( gx ), std::abs( gy ) );
        if ( filter == GradientFilter::ExtendedSobel )
        {
          const float gxy = 4.0f / 6.0f * ( ( at( r, c + 2 ) + 2 * at( r + 1, c + 1 ) + at( r + 2, c ) ) - ( at( r, c - 2 ) + 2 * at( r - 1, c - 1 ) + at( r - 2, c ) ) );
          const float gyx = 4.0f / 6.0f * ( ( at( r - 2, c ) + 2 * at( r - 1, c + 1 ) + at( r, c + 2 ) ) - ( at( r, c - 2 ) + 2 * at( r + 1, c - 1 ) + at( r + 2, c ) ) );
          g = std::max( { g, std::abs( gxy ), std::abs( gyx ) } );
        }
        out.at<float>( r, c ) = g;
      }
    return out;
  }

  cv::Mat lineFilterEdges( const cv::Mat &grey, double threshold )
  {
    requireGrey( grey );
    cv::Mat out( grey.size(), CV_8U, cv::Scalar( 0 ) );
    for ( int r = 0; r < grey.rows; ++r )
    {
      const uint8_t *g = grey.ptr<uint8_t>( r );
      for ( int c = 3; c + 3 < grey.cols; ++c )
      {
        const double centre = g[c];
        const bool darkLeft = centre - g[c - 3] > threshold && centre - g[c - 2] > threshold;
        const bool brightLeft = g[c - 3] - centre > threshold && g[c - 2] - centre > threshold;
        const bool darkRight = centre - g[c + 3] > threshold && centre - g[c + 2] > threshold;
        const bool brightRight = g[c + 3] - centre > threshold && g[c + 2] - centre > threshold;
        // a step: darker on one side, brighter on the other (a spike is darker or brighter on both)
        if ( ( darkLeft && brightRight ) || ( brightLeft && darkRight ) )
          out.at<uint8_t>( r, c ) = 255;
      }
    }
    return out;
  }

  cv::Mat binarise( const cv::Mat &value, double threshold )
  {
    cv::Mat out;
    cv::compare( value, threshold, out, cv::CMP_GT );
    return out;
  }

  int neighbourCode( const cv::Mat &binary, int col, int row )
  {
    int code = 0;
    for ( int i = 0; i < 8; ++i )
    {
      const int r = row + kRow[i], c = col + kCol[i];
      if ( r >= 0 && c >= 0 && r < binary.rows && c < binary.cols && binary.at<uint8_t>( r, c ) )
        code |= 1 << i;
    }
    return code;
  }

  const std::array<std::array<uint8_t, 256>, 2> &skeletonTables()
  {
    static const std::array<std::array<uint8_t, 256>, 2> tables = makeTables();
    return tables;
  }

  int skeletonise( cv::Mat &binary, int maxIterations )
  {
    if ( binary.empty() || binary.type() != CV_8UC1 )
      throw std::invalid_argument( "thinning needs a binary 8-bit single-band image" );
    const auto &tables = skeletonTables();
    int iteration = 0;
    for ( bool changed = true; changed && iteration < maxIterations; ++iteration )
    {
      changed = false;
      for ( int pass = 0; pass < 2; ++pass )
      {
        std::vector<cv::Point> remove;
        for ( int r = 0; r < binary.rows; ++r )
          for ( int c = 0; c < binary.cols; ++c )
            if ( binary.at<uint8_t>( r, c ) && tables[pass][neighbourCode( binary, c, r )] )
              remove.emplace_back( c, r );
        for ( const cv::Point &p : remove )
          binary.at<uint8_t>( p ) = 0;
        changed = changed || !remove.empty();
      }
    }
    return iteration;
  }

  std::vector<InterestPoint> forstnerPoints( const cv::Mat &grey, const ForstnerOptions &options, const std::optional<cv::Rect> &area )
  {
    requireGrey( grey );
    if ( options.window < 3 || options.window % 2 == 0 )
      throw std::invalid_argument( "the Förstner window must be odd and at least 3" );
    const cv::Rect full( 0, 0, grey.cols, grey.rows );
    const cv::Rect roi = area ? ( *area & full ) : full;
    const int h = options.window / 2;
    // gradients by central differences
    cv::Mat gx( grey.size(), CV_64F, cv::Scalar( 0 ) ), gy( grey.size(), CV_64F, cv::Scalar( 0 ) );
    for ( int r = 1; r + 1 < grey.rows; ++r )
      for ( int c = 1; c + 1 < grey.cols; ++c )
      {
        gx.at<double>( r, c ) = 0.5 * ( grey.at<uint8_t>( r, c + 1 ) - grey.at<uint8_t>( r, c - 1 ) );
        gy.at<double>( r, c ) = 0.5 * ( grey.at<uint8_t>( r + 1, c ) - grey.at<uint8_t>( r - 1, c ) );
      }
    cv::Mat weight( grey.size(), CV_64F, cv::Scalar( 0 ) ), roundness( grey.size(), CV_64F, cv::Scalar( 0 ) );
    double sum = 0.0;
    int count = 0;
    for ( int r = std::max( roi.y, h + 1 ); r < std::min( roi.y + roi.height, grey.rows - h - 1 ); ++r )
      for ( int c = std::max( roi.x, h + 1 ); c < std::min( roi.x + roi.width, grey.cols - h - 1 ); ++c )
      {
        double xx = 0, xy = 0, yy = 0;
        for ( int dr = -h; dr <= h; ++dr )
          for ( int dc = -h; dc <= h; ++dc )
          {
            const double a = gx.at<double>( r + dr, c + dc ), b = gy.at<double>( r + dr, c + dc );
            xx += a * a;
            xy += a * b;
            yy += b * b;
          }
        const double det = xx * yy - xy * xy, trace = xx + yy;
        if ( trace <= 0.0 )
          continue;
        weight.at<double>( r, c ) = det / trace;
        roundness.at<double>( r, c ) = 4.0 * det / ( trace * trace );
        sum += det / trace;
        ++count;
      }
    std::vector<InterestPoint> points;
    if ( count == 0 )
      return points;
    const double minWeight = options.weightFactor * sum / count;
    const int s = options.suppressionRadius;
    for ( int r = std::max( roi.y, h + 1 ); r < std::min( roi.y + roi.height, grey.rows - h - 1 ); ++r )
      for ( int c = std::max( roi.x, h + 1 ); c < std::min( roi.x + roi.width, grey.cols - h - 1 ); ++c )
      {
        const double w = weight.at<double>( r, c );
        if ( w <= minWeight || roundness.at<double>( r, c ) < options.minRoundness )
          continue;
        bool maximum = true;
        for ( int dr = -s; dr <= s && maximum; ++dr )
          for ( int dc = -s; dc <= s && maximum; ++dc )
          {
            const int rr = r + dr, cc = c + dc;
            if ( ( dr || dc ) && rr >= 0 && cc >= 0 && rr < grey.rows && cc < grey.cols )
              maximum = weight.at<double>( rr, cc ) < w || ( weight.at<double>( rr, cc ) == w && ( dr > 0 || ( dr == 0 && dc > 0 ) ) );
          }
        if ( !maximum )
          continue;
        // the point nearest to every gradient line of the window: N x = sum g g^T p
        Eigen::Matrix2d n = Eigen::Matrix2d::Zero();
        Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
        for ( int dr = -h; dr <= h; ++dr )
          for ( int dc = -h; dc <= h; ++dc )
          {
            const Eigen::Vector2d g( gx.at<double>( r + dr, c + dc ), gy.at<double>( r + dr, c + dc ) );
            const Eigen::Vector2d p( c + dc + 0.5, r + dr + 0.5 );
            const Eigen::Matrix2d ggt = g * g.transpose();
            n += ggt;
            rhs += ggt * p;
          }
        Eigen::Vector2d located = n.ldlt().solve( rhs );
        if ( !located.allFinite() || ( located - Eigen::Vector2d( c + 0.5, r + 0.5 ) ).norm() > h + 1 )
          located = Eigen::Vector2d( c + 0.5, r + 0.5 );
        points.push_back( { located, w, roundness.at<double>( r, c ) } );
      }
    return points;
  }

  std::optional<Eigen::Vector2d> centreOfGravity( const cv::Mat &grey, const Eigen::Vector2d &approximate, int halfSize, bool brightMark )
  {
    requireGrey( grey );
    const int c0 = static_cast<int>( std::floor( approximate.x() ) ) - halfSize, r0 = static_cast<int>( std::floor( approximate.y() ) ) - halfSize;
    const int size = 2 * halfSize + 1;
    if ( halfSize < 1 || c0 < 0 || r0 < 0 || c0 + size > grey.cols || r0 + size > grey.rows )
      return std::nullopt;
    std::vector<double> values;
    for ( int r = r0; r < r0 + size; ++r )
      for ( int c = c0; c < c0 + size; ++c )
        values.push_back( grey.at<uint8_t>( r, c ) );
    std::vector<double> sorted = values;
    std::nth_element( sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end() );
    const double background = sorted[sorted.size() / 2];
    double peak = 0.0;
    for ( double v : values )
      peak = std::max( peak, brightMark ? v - background : background - v );
    if ( peak < 3.0 )
      return std::nullopt; // no mark
    double sum = 0, sx = 0, sy = 0;
    for ( int r = r0, k = 0; r < r0 + size; ++r )
      for ( int c = c0; c < c0 + size; ++c, ++k )
      {
        const double excess = brightMark ? values[k] - background : background - values[k];
        if ( excess <= 0.25 * peak )
          continue;
        sum += excess;
        sx += excess * ( c + 0.5 );
        sy += excess * ( r + 0.5 );
      }
    return Eigen::Vector2d( sx / sum, sy / sum );
  }

  std::vector<Eigen::Vector2d> douglasPeucker( const std::vector<Eigen::Vector2d> &polyline, double tolerance )
  {
    if ( polyline.size() < 3 )
      return polyline;
    std::vector<char> keep( polyline.size(), 0 );
    keep.front() = keep.back() = 1;
    const std::function<void( size_t, size_t )> split = [&]( size_t first, size_t last )
    {
      const Eigen::Vector2d a = polyline[first], b = polyline[last];
      const Eigen::Vector2d ab = b - a;
      const double length = ab.norm();
      double worst = -1.0;
      size_t at = first;
      for ( size_t i = first + 1; i < last; ++i )
      {
        const Eigen::Vector2d ap = polyline[i] - a;
        const double d = length > 0.0 ? std::abs( ab.x() * ap.y() - ab.y() * ap.x() ) / length : ap.norm();
        if ( d > worst )
        {
          worst = d;
          at = i;
        }
      }
      if ( worst > tolerance )
      {
        keep[at] = 1;
        split( first, at );
        split( at, last );
      }
    };
    split( 0, polyline.size() - 1 );
    std::vector<Eigen::Vector2d> out;
    for ( size_t i = 0; i < polyline.size(); ++i )
      if ( keep[i] )
        out.push_back( polyline[i] );
    return out;
  }

} // namespace geostation
