/***************************************************************************
  markcandidates.cpp - candidates for signalised control points in a photo
 ***************************************************************************/
#include "identification/markcandidates.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "imageproc/edgeprimitives.h"

namespace geostation
{

  void MarkCandidateOptions::check() const
  {
    if ( !( minDiameterPx >= 1.0 ) )
      throw std::invalid_argument( "the smallest mark diameter must be at least 1 px" );
    if ( !( maxDiameterPx == 0.0 || ( maxDiameterPx >= minDiameterPx && maxDiameterPx <= 200.0 ) ) )
      throw std::invalid_argument( "the largest mark diameter must be 0 (a tenth of the image) or between the smallest and 200 px" );
    if ( !( minContrast > 0.0 ) )
      throw std::invalid_argument( "the mark contrast must be positive" );
    if ( !( minSideContrast >= 0.0 && minSideContrast <= 1.0 ) )
      throw std::invalid_argument( "the side contrast must be a fraction between 0 and 1" );
    if ( maxCandidates < 3 )
      throw std::invalid_argument( "at least 3 mark candidates must be kept" );
  }

  namespace
  {
    //! Sum over [c0, c1) x [r0, r1) of an integral image (CV_64F, one larger than the image).
    inline double boxSum( const cv::Mat &integral, int c0, int r0, int c1, int r1 )
    {
      return integral.at<double>( r1, c1 ) - integral.at<double>( r0, c1 ) - integral.at<double>( r1, c0 ) + integral.at<double>( r0, c0 );
    }

    //! The strongest Förstner point within `reach` of the mark's filter centre, in a crop around it.
    std::optional<Eigen::Vector2d> forstnerCentre( const cv::Mat &grey, const Eigen::Vector2d &centre, int half )
    {
      const int window = 2 * half + 3;
      const int margin = window / 2 + 2;
      const cv::Rect crop = cv::Rect( static_cast<int>( centre.x() ) - half - margin, static_cast<int>( centre.y() ) - half - margin,
                                      2 * ( half + margin ) + 1, 2 * ( half + margin ) + 1 ) & cv::Rect( 0, 0, grey.cols, grey.rows );
      if ( crop.width < window + 4 || crop.height < window + 4 )
        return std::nullopt;
      ForstnerOptions options;
      options.window = window;
      options.minRoundness = 0.3;
      options.weightFactor = 0.0;
      options.suppressionRadius = std::max( 1, half );
      const Eigen::Vector2d offset( crop.x, crop.y );
      std::optional<Eigen::Vector2d> best;
      double bestWeight = 0.0;
      for ( const InterestPoint &p : forstnerPoints( grey( crop ), options ) )
      {
        const Eigen::Vector2d at = p.pixelInImage + offset;
        if ( ( at - centre ).norm() <= half + 1.0 && p.weight > bestWeight )
        {
          bestWeight = p.weight;
          best = at;
        }
      }
      return best;
    }
  } // namespace

  double largestMarkPx( const MarkCandidateOptions &options, const cv::Size &size )
  {
    return options.maxDiameterPx > 0.0 ? options.maxDiameterPx : std::clamp( 0.1 * std::min( size.width, size.height ), std::max( 3.0, options.minDiameterPx ), 200.0 );
  }

  cv::Mat markGrey( const cv::Mat &image )
  {
    if ( image.empty() || ( image.depth() != CV_8U && image.depth() != CV_16U ) || ( image.channels() != 1 && image.channels() != 3 && image.channels() != 4 ) )
      throw std::invalid_argument( "marks are looked for in an 8- or 16-bit grey, RGB or RGBA image" );
    cv::Mat grey;
    if ( image.channels() == 1 )
      grey = image;
    else
      cv::cvtColor( image, grey, image.channels() == 3 ? cv::COLOR_RGB2GRAY : cv::COLOR_RGBA2GRAY );
    if ( grey.depth() == CV_8U )
      return grey.clone();
    std::vector<uint16_t> values;
    const int step = std::max( 1, static_cast<int>( grey.total() / 200000 ) );
    for ( size_t k = 0; k < grey.total(); k += step )
      values.push_back( grey.at<uint16_t>( static_cast<int>( k / grey.cols ), static_cast<int>( k % grey.cols ) ) );
    std::sort( values.begin(), values.end() );
    const double lo = values[values.size() / 1000], hi = std::max<double>( lo + 1, values[values.size() - 1 - values.size() / 1000] );
    cv::Mat out;
    grey.convertTo( out, CV_8U, 255.0 / ( hi - lo ), -255.0 * lo / ( hi - lo ) );
    return out;
  }

  std::vector<MarkCandidate> detectMarkCandidates( const cv::Mat &grey, const MarkCandidateOptions &options )
  {
    if ( grey.empty() || grey.type() != CV_8UC1 )
      throw std::invalid_argument( "mark candidates are found in an 8-bit grey image" );
    options.check();
    cv::Mat integral;
    cv::integral( grey, integral, CV_64F );
    const double sign = options.brightMark ? 1.0 : -1.0;
    // the best centre-surround response over the sizes and flattenings, per pixel
    struct Shape
    {
      int hx, hy; //!< half sizes of the mark's box; the ring reaches as far again
    };
    std::vector<Shape> shapes;
    const double maxDiameter = largestMarkPx( options, grey.size() );
    for ( double d = options.minDiameterPx; d <= maxDiameter * 1.0001; d *= 1.35 )
    {
      const int hx = std::max( 1, static_cast<int>( std::lround( 0.5 * d ) ) );
      for ( double flattening : { 1.0, 0.6, 0.35 } ) // a disc seen obliquely is an ellipse, flatter across the view
      {
        const Shape shape { hx, std::max( 1, static_cast<int>( std::lround( hx * flattening ) ) ) };
        if ( std::none_of( shapes.begin(), shapes.end(), [&]( const Shape &o ) { return o.hx == shape.hx && o.hy == shape.hy; } ) )
          shapes.push_back( shape );
      }
    }
    cv::Mat best( grey.size(), CV_32F, cv::Scalar( 0 ) ), bestShape( grey.size(), CV_32S, cv::Scalar( -1 ) );
    for ( int k = 0; k < static_cast<int>( shapes.size() ); ++k )
    {
      const int hx = shapes[k].hx, hy = shapes[k].hy, ox = 2 * hx, oy = 2 * hy;
      const double innerArea = ( 2.0 * hx + 1 ) * ( 2.0 * hy + 1 ), outerArea = ( 2.0 * ox + 1 ) * ( 2.0 * oy + 1 );
      for ( int r = oy; r + oy < grey.rows; ++r )
      {
        float *bestRow = best.ptr<float>( r );
        int *shapeRow = bestShape.ptr<int>( r );
        for ( int c = ox; c + ox < grey.cols; ++c )
        {
          const double inner = boxSum( integral, c - hx, r - hy, c + hx + 1, r + hy + 1 );
          const double all = boxSum( integral, c - ox, r - oy, c + ox + 1, r + oy + 1 );
          const double response = sign * ( inner / innerArea - ( all - inner ) / ( outerArea - innerArea ) );
          if ( response > bestRow[c] )
          {
            bestRow[c] = static_cast<float>( response );
            shapeRow[c] = k;
          }
        }
      }
    }
    // local maxima over position (within the size that answered)
    std::vector<MarkCandidate> found;
    for ( int r = 0; r < grey.rows; ++r )
      for ( int c = 0; c < grey.cols; ++c )
      {
        const float v = best.at<float>( r, c );
        if ( v < options.minContrast )
          continue;
        const Shape shape = shapes[bestShape.at<int>( r, c )];
        const int reach = std::max( 2, shape.hx );
        bool maximum = true;
        for ( int dr = -reach; dr <= reach && maximum; ++dr )
          for ( int dc = -reach; dc <= reach && maximum; ++dc )
          {
            const int rr = r + dr, cc = c + dc;
            if ( ( dr || dc ) && rr >= 0 && cc >= 0 && rr < grey.rows && cc < grey.cols )
            {
              const float w = best.at<float>( rr, cc );
              maximum = w < v || ( w == v && ( dr > 0 || ( dr == 0 && dc > 0 ) ) );
            }
          }
        if ( !maximum )
          continue;
        // a compact mark stands out on every side; the sky above a ridge, a bright edge or a stripe does not
        const int hx = shape.hx, hy = shape.hy, ox = 2 * hx, oy = 2 * hy;
        const double inner = sign * boxSum( integral, c - hx, r - hy, c + hx + 1, r + hy + 1 ) / ( ( 2.0 * hx + 1 ) * ( 2.0 * hy + 1 ) );
        const double above = boxSum( integral, c - hx, r - oy, c + hx + 1, r - hy ), below = boxSum( integral, c - hx, r + hy + 1, c + hx + 1, r + oy + 1 );
        const double left = boxSum( integral, c - ox, r - hy, c - hx, r + hy + 1 ), right = boxSum( integral, c + hx + 1, r - hy, c + ox + 1, r + hy + 1 );
        const double rowArea = ( 2.0 * hx + 1 ) * hy, columnArea = ( 2.0 * hy + 1 ) * hx;
        bool compact = true;
        for ( double side : { above / rowArea, below / rowArea, left / columnArea, right / columnArea } )
          compact = compact && inner - sign * side >= options.minSideContrast * v;
        if ( !compact )
          continue;
        MarkCandidate candidate;
        candidate.pixelInImage = Eigen::Vector2d( c + 0.5, r + 0.5 );
        candidate.contrast = v;
        candidate.diameterPx = 2.0 * hx + 1.0;
        found.push_back( candidate );
      }
    std::sort( found.begin(), found.end(), []( const MarkCandidate &a, const MarkCandidate &b ) { return a.contrast > b.contrast; } );
    // locate the strongest; two that land on one mark are one candidate
    std::vector<MarkCandidate> kept;
    for ( MarkCandidate &candidate : found )
    {
      if ( static_cast<int>( kept.size() ) >= options.maxCandidates )
        break;
      const int half = static_cast<int>( candidate.diameterPx / 2 );
      std::optional<Eigen::Vector2d> gravity = centreOfGravity( grey, candidate.pixelInImage, half + 1, options.brightMark );
      if ( gravity && ( *gravity - candidate.pixelInImage ).norm() > half + 1.0 )
        gravity.reset();
      // Förstner's point where it agrees with the centre of gravity (a small mark, a square's corners); on a
      // large disc in a ring it may be a point of the outline, the strongest corner within its window
      const std::optional<Eigen::Vector2d> located = forstnerCentre( grey, candidate.pixelInImage, half );
      if ( located && ( !gravity || ( *located - *gravity ).norm() <= 1.0 ) )
      {
        candidate.pixelInImage = *located;
        candidate.forstner = true;
      }
      else if ( gravity )
        candidate.pixelInImage = *gravity;
      // a mark the frame cuts is located at the centre of what is left of it
      const double margin = 0.5 * candidate.diameterPx + 1.0;
      if ( candidate.pixelInImage.x() < margin || candidate.pixelInImage.y() < margin || candidate.pixelInImage.x() > grey.cols - margin ||
           candidate.pixelInImage.y() > grey.rows - margin )
        continue;
      const bool duplicate = std::any_of( kept.begin(), kept.end(), [&]( const MarkCandidate &k ) {
        return ( k.pixelInImage - candidate.pixelInImage ).norm() < std::max( 2.0, 0.5 * k.diameterPx );
      } );
      if ( !duplicate )
        kept.push_back( candidate );
    }
    return kept;
  }

} // namespace geostation
