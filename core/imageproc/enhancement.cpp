/***************************************************************************
  enhancement.cpp - stretches, equalisation, add-back sharpening, box filter
 ***************************************************************************/
#include "imageproc/enhancement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace geostation
{
  namespace
  {
    const std::pair<EnhancementMethod, const char *> kNames[] = {
      { EnhancementMethod::Equalise, "equalise" }, { EnhancementMethod::LinearStretch, "linear" },
      { EnhancementMethod::TwoSegmentStretch, "two_segment" }, { EnhancementMethod::ThreeSegmentStretch, "three_segment" },
      { EnhancementMethod::SobelAddBack, "sobel_addback" }, { EnhancementMethod::DifferenceAddBack, "difference_addback" },
      { EnhancementMethod::AdaptiveBoxFilter, "box_filter" } };

    //! Luminance of the region as doubles (the band itself for grey images).
    cv::Mat luminance( const cv::Mat &region )
    {
      cv::Mat grey;
      if ( region.channels() == 3 )
        cv::cvtColor( region, grey, cv::COLOR_RGB2GRAY );
      else
        grey = region;
      cv::Mat out;
      grey.convertTo( out, CV_64F );
      return out;
    }

    //! Applies a level mapping to every band of `region` in place.
    template <typename T>
    void applyLevels( cv::Mat &region, const std::vector<double> &lut, double maxValue )
    {
      for ( int r = 0; r < region.rows; ++r )
      {
        T *p = region.ptr<T>( r );
        for ( int k = 0; k < region.cols * region.channels(); ++k )
          p[k] = static_cast<T>( std::clamp( std::lround( lut[p[k]] ), 0L, static_cast<long>( maxValue ) ) );
      }
    }

    //! The diagonal and axis gradients of eqs. 4.10 and 4.12 at (r, c) of a band, the largest by magnitude.
    double strongestGradient( const cv::Mat &g, int r, int c )
    {
      const auto at = [&]( int dr, int dc )
      {
        return g.at<double>( std::clamp( r + dr, 0, g.rows - 1 ), std::clamp( c + dc, 0, g.cols - 1 ) );
      };
      // 3 x 3: a b c / d e f / g h i
      const double gx = ( at( 1, -1 ) + 2 * at( 1, 0 ) + at( 1, 1 ) ) - ( at( -1, -1 ) + 2 * at( -1, 0 ) + at( -1, 1 ) );
      const double gy = ( at( -1, 1 ) + 2 * at( 0, 1 ) + at( 1, 1 ) ) - ( at( -1, -1 ) + 2 * at( 0, -1 ) + at( 1, -1 ) );
      // the diagonals, on the extended neighbourhood (eq. 4.12): the pixels on either side of e
      // one diagonal step away, the nearest twice, weighted 4/6
      const double gxy = 4.0 / 6.0 * ( ( at( 0, 2 ) + 2 * at( 1, 1 ) + at( 2, 0 ) ) - ( at( 0, -2 ) + 2 * at( -1, -1 ) + at( -2, 0 ) ) );
      const double gyx = 4.0 / 6.0 * ( ( at( -2, 0 ) + 2 * at( -1, 1 ) + at( 0, 2 ) ) - ( at( 0, -2 ) + 2 * at( 1, -1 ) + at( 2, 0 ) ) );
      double best = gx;
      for ( double v : { gy, gxy, gyx } )
        if ( std::abs( v ) > std::abs( best ) )
          best = v;
      return best;
    }

    /**
     * The adaptive box filter (eqs. 6.2-6.8) of one band `g` (CV_64F) into
     * `result` (a copy of it): a value farther from its box's mean than boxC
     * sigma and boxT grey levels (8-bit levels times k) takes the mean of
     * the others. Returns the pixels changed.
     */
    long replaceOutliers( const cv::Mat &g, cv::Mat &result, const EnhancementOptions &options, double k )
    {
      // box sums of the values and their squares (every value of the type is valid, eq. 6.1)
      cv::Mat sum, sumSq, squares;
      const cv::Size box( 2 * options.boxHalfWidth + 1, 2 * options.boxHalfHeight + 1 );
      cv::boxFilter( g, sum, CV_64F, box, cv::Point( -1, -1 ), false, cv::BORDER_REFLECT );
      cv::multiply( g, g, squares );
      cv::boxFilter( squares, sumSq, CV_64F, box, cv::Point( -1, -1 ), false, cv::BORDER_REFLECT );
      const double n = box.area();
      long changed = 0;
      for ( int r = 0; r < g.rows; ++r )
        for ( int c = 0; c < g.cols; ++c )
        {
          const double v = g.at<double>( r, c ), S = sum.at<double>( r, c );
          const double M = S / n;                                                  // eq. 6.5
          const double sigma = std::sqrt( std::max( 0.0, sumSq.at<double>( r, c ) / n - M * M ) ); // eq. 6.7
          if ( std::abs( v - M ) > options.boxC * sigma && std::abs( v - M ) > options.boxT * k ) // eq. 6.8
          {
            result.at<double>( r, c ) = ( S - v ) / ( n - 1 ); // eq. 6.6
            ++changed;
          }
        }
      return changed;
    }

    /**
     * Edge enhancement by adding back (eqs. 4.13-4.16) of one band `g`
     * (CV_64F) into `result` (a copy of it): the strongest Sobel gradient or
     * the largest difference to the eight neighbours, scaled, added where it
     * exceeds the threshold (8-bit levels times k). Returns the pixels changed.
     */
    long addBackEdges( const cv::Mat &g, cv::Mat &result, const EnhancementOptions &options, double k )
    {
      long changed = 0;
      for ( int r = 0; r < g.rows; ++r )
        for ( int c = 0; c < g.cols; ++c )
        {
          double G;
          if ( options.method == EnhancementMethod::SobelAddBack )
            G = strongestGradient( g, r, c ); // eq. 4.14
          else
          {
            // eq. 4.15: the largest difference to the eight neighbours
            G = -1e300;
            for ( int dr = -1; dr <= 1; ++dr )
              for ( int dc = -1; dc <= 1; ++dc )
                if ( dr || dc )
                  G = std::max( G, g.at<double>( r, c ) - g.at<double>( std::clamp( r + dr, 0, g.rows - 1 ), std::clamp( c + dc, 0, g.cols - 1 ) ) );
          }
          if ( std::abs( G ) > options.threshold * k ) // eqs. 4.13, 4.16
          {
            result.at<double>( r, c ) = g.at<double>( r, c ) + options.scale * G;
            ++changed;
          }
        }
      return changed;
    }
  }

  std::string enhancementMethodName( EnhancementMethod method )
  {
    for ( const auto &[m, name] : kNames )
      if ( m == method )
        return name;
    return "three_segment";
  }

  std::optional<EnhancementMethod> enhancementMethodFromName( const std::string &name )
  {
    for ( const auto &[m, n] : kNames )
      if ( name == n )
        return m;
    return std::nullopt;
  }

  void EnhancementOptions::validate() const
  {
    const auto require = []( bool ok, const char *what )
    {
      if ( !ok )
        throw std::invalid_argument( what );
    };
    require( outLow >= 0 && outHigh <= 255 && outLow < outHigh, "the output range must lie in 0..255 with low below high" );
    require( clipPercent >= 0 && clipPercent < 50, "the clip percentage must be between 0 and 50" );
    require( preferredMean > 0 && preferredMean < 255, "the preferred mean must be between 0 and 255" );
    require( threeSegmentWidth > 0 && threeSegmentWidth < 255 && threeSegmentTarget > 0 && threeSegmentTarget < 255,
             "the three-segment width and target must be between 0 and 255" );
    require( scale > 0 && scale < 1, "the add-back scale must be between 0 and 1" );
    require( threshold >= 0, "the threshold must not be negative" );
    require( boxHalfWidth >= 1 && boxHalfHeight >= 1 && boxHalfWidth <= 50 && boxHalfHeight <= 50, "the box half sizes must be between 1 and 50" );
    require( boxC >= 0.5 && boxC <= 5 && boxT >= 0, "the box filter needs C between 0.5 and 5 and T >= 0" );
  }

  cv::Mat enhanceImage( const cv::Mat &image, const EnhancementOptions &options, EnhancementSummary *summary )
  {
    options.validate();
    if ( image.empty() || ( image.depth() != CV_8U && image.depth() != CV_16U ) || ( image.channels() != 1 && image.channels() != 3 ) )
      throw std::invalid_argument( "enhancement needs an 8- or 16-bit image with 1 or 3 bands" );
    const cv::Rect full( 0, 0, image.cols, image.rows );
    const cv::Rect roi = options.window ? ( *options.window & full ) : full;
    if ( roi.area() <= 0 )
      throw std::invalid_argument( "the window lies outside the image" );
    const double maxValue = image.depth() == CV_8U ? 255.0 : 65535.0;
    const double k = maxValue / 255.0; // Xin's (1995) 8-bit levels, scaled
    cv::Mat out = image.clone();
    cv::Mat region = out( roi );

    const cv::Mat grey = luminance( image( roi ) );
    double lo = 0, hi = 0;
    cv::minMaxLoc( grey, &lo, &hi );
    const double mean = cv::mean( grey )[0];
    EnhancementSummary s;
    s.mean = mean;
    s.min = lo;
    s.max = hi;

    const auto levels = [&]( auto &&mapping )
    {
      std::vector<double> lut( static_cast<size_t>( maxValue ) + 1 );
      for ( size_t g = 0; g < lut.size(); ++g )
        lut[g] = mapping( static_cast<double>( g ) );
      if ( image.depth() == CV_8U )
        applyLevels<uint8_t>( region, lut, maxValue );
      else
        applyLevels<uint16_t>( region, lut, maxValue );
    };

    switch ( options.method )
    {
      case EnhancementMethod::Equalise:
      {
        std::vector<double> cdf( static_cast<size_t>( maxValue ) + 1, 0.0 );
        for ( int r = 0; r < grey.rows; ++r )
          for ( int c = 0; c < grey.cols; ++c )
            cdf[static_cast<size_t>( grey.at<double>( r, c ) )] += 1.0;
        for ( size_t i = 1; i < cdf.size(); ++i )
          cdf[i] += cdf[i - 1];
        const double n = static_cast<double>( grey.total() );
        levels( [&]( double g ) { return cdf[static_cast<size_t>( g )] / n * maxValue; } ); // eqs. 4.2-4.4
        break;
      }
      case EnhancementMethod::LinearStretch:
      {
        double a = lo, b = hi;
        if ( options.clipPercent > 0 )
        {
          std::vector<double> values( grey.begin<double>(), grey.end<double>() );
          const size_t cut = static_cast<size_t>( values.size() * options.clipPercent / 100.0 );
          std::nth_element( values.begin(), values.begin() + cut, values.end() );
          a = values[cut];
          std::nth_element( values.begin(), values.end() - 1 - cut, values.end() );
          b = values[values.size() - 1 - cut];
        }
        const double outLow = options.outLow * k, outHigh = options.outHigh * k;
        levels( [&]( double g ) { return b > a ? ( g - a ) / ( b - a ) * ( outHigh - outLow ) + outLow : g; } ); // eq. 4.5
        break;
      }
      case EnhancementMethod::TwoSegmentStretch:
      {
        const double pmean = options.preferredMean * k;
        levels( [&]( double g )
        {
          if ( g < mean ) // eq. 4.6a
            return mean > lo ? pmean / ( mean - lo ) * ( g - lo ) : pmean;
          return hi > mean ? ( maxValue - pmean ) / ( hi - mean ) * ( g - mean ) + pmean : pmean; // eq. 4.6b
        } );
        break;
      }
      case EnhancementMethod::ThreeSegmentStretch:
      {
        const double a = mean, b = mean + options.threeSegmentWidth * k, a2 = options.threeSegmentTarget * k;
        levels( [&]( double g )
        {
          if ( g <= a ) // eq. 4.7a
            return a > lo ? a2 / ( a - lo ) * ( g - lo ) : a2;
          if ( g <= b ) // eq. 4.7b
            return g - a + a2;
          const double top = a2 + ( b - a ); // eq. 4.7c
          return hi > b ? ( maxValue - top ) / ( hi - b ) * ( g - b ) + top : top;
        } );
        break;
      }
      case EnhancementMethod::SobelAddBack:
      case EnhancementMethod::DifferenceAddBack:
      case EnhancementMethod::AdaptiveBoxFilter:
      {
        std::vector<cv::Mat> bands;
        cv::split( region, bands );
        for ( cv::Mat &band : bands )
        {
          cv::Mat g;
          band.convertTo( g, CV_64F );
          cv::Mat result = g.clone();
          s.changedPixels += options.method == EnhancementMethod::AdaptiveBoxFilter ? replaceOutliers( g, result, options, k ) : addBackEdges( g, result, options, k );
          result.convertTo( band, band.type() ); // rounds and saturates
        }
        cv::merge( bands, region );
        break;
      }
    }
    if ( summary )
      *summary = s;
    return out;
  }

} // namespace geostation
