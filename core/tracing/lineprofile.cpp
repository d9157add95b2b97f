/***************************************************************************
  lineprofile.cpp - the road line across its direction
 ***************************************************************************/
#include "tracing/lineprofile.h"
#include "geometry/rotation.h"
#include "tracing/linetrace.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

namespace geostation
{
  namespace
  {
    //! Grey values at integer offsets -half..half across the line, averaged along it; NaN outside the image.
    std::vector<double> crossProfile( const cv::Mat &grey, const Eigen::Vector2d &centre, const Eigen::Vector2d &direction, int half, int alongSamples )
    {
      const Eigen::Vector2d normal = rightNormal( direction );
      std::vector<double> values( 2 * half + 1, std::nan( "" ) );
      for ( int u = -half; u <= half; ++u )
      {
        double sum = 0.0;
        int n = 0;
        for ( int k = 0; k < alongSamples; ++k )
        {
          const double t = k - 0.5 * ( alongSamples - 1 );
          if ( const std::optional<double> g = sampleGrey( grey, centre + u * normal + t * direction ) )
          {
            sum += *g;
            ++n;
          }
        }
        if ( n == alongSamples )
          values[u + half] = sum / n;
      }
      return values;
    }

    std::optional<LineHit> locateEdge( const std::vector<double> &p, int half, int polarity, const LocateOptions &options )
    {
      const int search = static_cast<int>( std::ceil( options.searchHalfPx ) );
      const auto at = [&]( int u ) { return p[u + half]; };
      std::optional<LineHit> best;
      for ( int u = -search; u <= search; ++u )
      {
        if ( u - 4 < -half || u + 4 > half )
          continue;
        const auto d = [&]( int v ) { return polarity * 0.5 * ( at( v + 1 ) - at( v - 1 ) ); };
        const double d0 = d( u ), dm = d( u - 1 ), dp = d( u + 1 );
        if ( std::isnan( d0 ) || std::isnan( dm ) || std::isnan( dp ) || d0 <= 0.0 || d0 < dm || d0 < dp )
          continue;
        const double step = polarity * ( at( u + 3 ) - at( u - 3 ) );
        if ( std::isnan( step ) || step < options.minContrast )
          continue;
        const double curvature = dm - 2 * d0 + dp;
        const double shift = curvature < 0 ? std::clamp( 0.5 * ( dm - dp ) / curvature, -0.5, 0.5 ) : 0.0;
        const double offset = u + shift;
        if ( std::abs( offset ) > options.searchHalfPx || ( best && std::abs( offset ) >= std::abs( best->offsetPx ) ) )
          continue;
        LineHit hit;
        hit.offsetPx = offset;
        hit.contrast = step;
        hit.sigmaPx = std::clamp( options.noiseGrey / ( std::sqrt( static_cast<double>( options.alongSamples ) ) * d0 ) * 2.0, 0.1, 1.0 );
        best = hit;
      }
      return best;
    }

    std::optional<LineHit> locateStripe( std::vector<double> p, int half, bool bright, double expectedWidth, const LocateOptions &options )
    {
      if ( !bright )
        for ( double &v : p )
          v = -v;
      const int h = std::max( 2, static_cast<int>( std::lround( 0.5 * expectedWidth + 1.5 ) ) );
      const int search = static_cast<int>( std::ceil( options.searchHalfPx ) );
      const auto at = [&]( int u ) { return ( u < -half || u > half ) ? std::nan( "" ) : p[u + half]; };
      const auto response = [&]( int u ) { return at( u ) - 0.5 * ( at( u - h ) + at( u + h ) ); };
      std::optional<LineHit> best;
      for ( int u = -search - 1; u <= search + 1; ++u )
      {
        const double r = response( u ), rm = response( u - 1 ), rp = response( u + 1 );
        if ( std::isnan( r ) || std::isnan( rm ) || std::isnan( rp ) || r < options.minContrast || r < rm || r < rp )
          continue;
        // background either side, peak, then the half-contrast crossings
        const double background = 0.5 * ( at( u - h ) + at( u + h ) );
        double peak = at( u );
        for ( int v = u - 1; v <= u + 1; ++v )
          peak = std::max( peak, at( v ) );
        const double level = background + 0.5 * ( peak - background );
        double left = std::nan( "" ), right = std::nan( "" );
        for ( int v = u; v - 1 >= -half; --v )
          if ( at( v - 1 ) <= level )
          {
            left = v - ( at( v ) - level ) / ( at( v ) - at( v - 1 ) );
            break;
          }
        for ( int v = u; v + 1 <= half; ++v )
          if ( at( v + 1 ) <= level )
          {
            right = v + ( at( v ) - level ) / ( at( v ) - at( v + 1 ) );
            break;
          }
        if ( std::isnan( left ) || std::isnan( right ) )
          continue;
        const double width = right - left, offset = 0.5 * ( left + right );
        if ( expectedWidth > 0 && ( width > options.maxWidthRatio * expectedWidth + 1.0 || width < expectedWidth / options.minWidthRatio - 1.0 ) )
          continue;
        if ( std::abs( offset ) > options.searchHalfPx + 0.5 || ( best && std::abs( offset ) >= std::abs( best->offsetPx ) ) )
          continue;
        LineHit hit;
        hit.offsetPx = offset;
        hit.contrast = peak - background;
        hit.widthPx = width;
        hit.sigmaPx = std::clamp( options.noiseGrey * std::sqrt( std::max( width, 1.0 ) ) / ( std::sqrt( static_cast<double>( options.alongSamples ) ) * hit.contrast ) * 2.0, 0.1, 1.0 );
        best = hit;
      }
      return best;
    }

    //! The line direction from the structure tensor of a window (perpendicular to the dominant gradient).
    std::optional<Eigen::Vector2d> tensorDirection( const cv::Mat &grey, const Eigen::Vector2d &centre, int window )
    {
      const int half = window / 2 + 1;
      const cv::Rect box( static_cast<int>( centre.x() ) - half, static_cast<int>( centre.y() ) - half, 2 * half + 1, 2 * half + 1 );
      const cv::Rect clipped = box & cv::Rect( 0, 0, grey.cols, grey.rows );
      if ( clipped.width < 7 || clipped.height < 7 )
        return std::nullopt;
      cv::Mat gx, gy;
      cv::Sobel( grey( clipped ), gx, CV_32F, 1, 0 );
      cv::Sobel( grey( clipped ), gy, CV_32F, 0, 1 );
      double jxx = 0, jyy = 0, jxy = 0;
      for ( int r = 1; r < clipped.height - 1; ++r )
        for ( int c = 1; c < clipped.width - 1; ++c )
        {
          const double x = gx.at<float>( r, c ), y = gy.at<float>( r, c );
          jxx += x * x;
          jyy += y * y;
          jxy += x * y;
        }
      if ( jxx + jyy <= 0 )
        return std::nullopt;
      const double gradientAngle = 0.5 * std::atan2( 2 * jxy, jxx - jyy );
      return Eigen::Vector2d( -std::sin( gradientAngle ), std::cos( gradientAngle ) );
    }

    Eigen::Vector2d upOrRight( Eigen::Vector2d d )
    {
      d.normalize();
      if ( d.y() > 0.2 || ( std::abs( d.y() ) <= 0.2 && d.x() < 0 ) )
        d = -d;
      return d;
    }
  }

  std::optional<double> sampleGrey( const cv::Mat &grey, const Eigen::Vector2d &pixelInImage )
  {
    const double x = pixelInImage.x() - 0.5, y = pixelInImage.y() - 0.5;
    if ( !( x >= 0.0 && y >= 0.0 && x <= grey.cols - 1 && y <= grey.rows - 1 ) )
      return std::nullopt;
    const int x0 = std::min( static_cast<int>( x ), grey.cols - 2 ), y0 = std::min( static_cast<int>( y ), grey.rows - 2 );
    const double u = x - x0, v = y - y0;
    const uint8_t *a = grey.ptr<uint8_t>( y0 ) + x0, *b = grey.ptr<uint8_t>( y0 + 1 ) + x0;
    return ( 1 - v ) * ( ( 1 - u ) * a[0] + u * a[1] ) + v * ( ( 1 - u ) * b[0] + u * b[1] );
  }

  std::optional<LineHit> locateLine( const cv::Mat &grey, const Eigen::Vector2d &centre, const Eigen::Vector2d &direction, const LineProfile &profile,
                                     const LocateOptions &options )
  {
    const bool stripe = profile.kind != LineKind::Edge;
    const int margin = stripe ? static_cast<int>( std::ceil( 0.5 * options.maxWidthRatio * std::max( profile.widthPx, 1.0 ) ) ) + 4 : 5;
    const int half = static_cast<int>( std::ceil( options.searchHalfPx ) ) + margin;
    const std::vector<double> p = crossProfile( grey, centre, direction, half, options.alongSamples );
    const std::optional<LineHit> hit = stripe ? locateStripe( p, half, profile.kind == LineKind::BrightStripe, profile.widthPx, options )
                                              : locateEdge( p, half, profile.polarity, options );
    if ( !hit )
      return std::nullopt;
    LineHit out = *hit;
    out.pixelInImage = centre + out.offsetPx * rightNormal( direction );
    return out;
  }

  std::optional<LineSides> lineSides( const cv::Mat &grey, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &direction, const LineProfile &profile )
  {
    const Eigen::Vector2d normal = rightNormal( direction );
    const double from = profile.kind == LineKind::Edge ? 3.0 : 0.5 * profile.widthPx + 2.0;
    LineSides out;
    double centre = 0.0;
    for ( int k = -1; k <= 1; ++k )
    {
      const std::optional<double> onLine = sampleGrey( grey, pixelInImage + k * direction );
      if ( !onLine )
        return std::nullopt;
      centre += *onLine / 3.0;
      for ( const int side : { -1, 1 } )
        for ( int u = 0; u < 4; ++u )
        {
          const std::optional<double> beside = sampleGrey( grey, pixelInImage + side * ( from + u ) * normal + k * direction );
          if ( !beside )
            return std::nullopt;
          ( side < 0 ? out.left : out.right ) += *beside / 12.0;
        }
    }
    out.contrast = profile.kind == LineKind::Edge ? std::abs( out.right - out.left ) : std::abs( centre - 0.5 * ( out.left + out.right ) );
    return out;
  }

  bool sidesAgree( const LineSides &reference, const LineSides &seen, double toleranceGrey )
  {
    const double power = seen.left * seen.left + seen.right * seen.right;
    const double gain = power > 0.0 ? std::clamp( ( seen.left * reference.left + seen.right * reference.right ) / power, 0.4, 2.5 ) : 1.0;
    return std::abs( gain * seen.left - reference.left ) <= toleranceGrey && std::abs( gain * seen.right - reference.right ) <= toleranceGrey;
  }

  LocateOptions locateOptionsFor( const LineProfile &profile, const FollowOptions &follow, double searchHalfPx )
  {
    LocateOptions options;
    options.searchHalfPx = searchHalfPx;
    options.minContrast = std::max( follow.minContrastGrey, follow.minContrastFraction * profile.contrast );
    return options;
  }

  namespace
  {
    //! The direction of a set of points (their scatter's principal axis), unit length; none for fewer than two.
    std::optional<Eigen::Vector2d> principalDirection( const std::vector<Eigen::Vector2d> &points )
    {
      if ( points.size() < 2 )
        return std::nullopt;
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for ( const Eigen::Vector2d &p : points )
        mean += p;
      mean /= static_cast<double>( points.size() );
      Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
      for ( const Eigen::Vector2d &p : points )
        scatter += ( p - mean ) * ( p - mean ).transpose();
      if ( scatter.trace() <= 0 )
        return std::nullopt;
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen( scatter );
      return Eigen::Vector2d( eigen.eigenvectors().col( 1 ).normalized() );
    }

    //! A stripe's full width and centre line beyond a stretch where it is worn to part of its width.
    struct WornStripe
    {
      double widthPx = 0.0;                                      //!< median of the wider hits
      Eigen::Vector2d onCentreLine = Eigen::Vector2d::Zero();    //!< the hits' mean
      Eigen::Vector2d course = Eigen::Vector2d( 0, -1 );         //!< the centre line's direction (unit)
    };

    /**
     * A stripe at `pixel` worn to part of its width over a stretch: where it
     * is found 1.4 times as wide or more 18-30 px along `direction`, at 3 or
     * more of those 6 positions, all on one course within 1 px, and the paint
     * at `pixel` inside their width. Nothing otherwise (on cobbles two dark
     * patches beside a kerb's far end are wider too). Towards a forward
     * camera (down the image) perspective widens a line too, so wider hits
     * must include 2 up the image, or else be all 3 down it with the line up
     * the image found at 2 or more positions as wide as at `pixel` (within
     * 0.8-1.25): where perspective makes a line 1.4 times as wide 18 px down,
     * it makes it 0.6 times as wide or less 18 px up; worn paint stays as
     * narrow up to the wear's end.
     */
    std::optional<WornStripe> wornBeyond( const cv::Mat &grey, const Eigen::Vector2d &pixel, const Eigen::Vector2d &direction, const LineProfile &profile, double widthPx )
    {
      LocateOptions either = locateOptionsFor( profile, FollowOptions(), 3.0 );
      either.maxWidthRatio = either.minWidthRatio = 2.5;
      std::vector<Eigen::Vector2d> centres;
      std::vector<double> widths;
      int up = 0, asNarrowUp = 0;
      for ( const double step : { -30.0, -24.0, -18.0, 18.0, 24.0, 30.0 } )
        if ( const std::optional<LineHit> h = locateLine( grey, pixel + step * direction, direction, profile, either ) )
        {
          const bool isUp = step * direction.y() < 0;
          if ( h->widthPx >= 1.4 * widthPx )
          {
            centres.push_back( h->pixelInImage );
            widths.push_back( h->widthPx );
            up += isUp;
          }
          else if ( isUp && h->widthPx >= 0.8 * widthPx && h->widthPx <= 1.25 * widthPx )
            ++asNarrowUp;
        }
      const bool wornUpTheImage = up == 0 && centres.size() == 3 && asNarrowUp >= 2;
      if ( centres.size() < 3 || ( up < 2 && !wornUpTheImage ) )
        return std::nullopt;
      // one stripe: the wider hits on one course (within 1 px), the paint left at the click inside its full width
      const std::optional<Eigen::Vector2d> course = principalDirection( centres );
      if ( !course || std::abs( course->dot( direction ) ) < std::cos( 10.0 * kPi / 180.0 ) )
        return std::nullopt;
      WornStripe out;
      out.course = course->dot( direction ) < 0 ? Eigen::Vector2d( -*course ) : *course;
      out.onCentreLine = std::accumulate( centres.begin(), centres.end(), Eigen::Vector2d( Eigen::Vector2d::Zero() ) ) / static_cast<double>( centres.size() );
      const Eigen::Vector2d normal( -out.course.y(), out.course.x() );
      for ( const Eigen::Vector2d &c : centres )
        if ( std::abs( normal.dot( c - out.onCentreLine ) ) > 1.0 )
          return std::nullopt;
      const double meanWidth = std::accumulate( widths.begin(), widths.end(), 0.0 ) / static_cast<double>( widths.size() );
      if ( std::abs( normal.dot( pixel - out.onCentreLine ) ) > 0.5 * meanWidth + 1.0 )
        return std::nullopt;
      std::nth_element( widths.begin(), widths.begin() + widths.size() / 2, widths.end() );
      out.widthPx = widths[widths.size() / 2];
      return out;
    }

    /**
     * A stripe found at a click (`hit`) worn there to part of its width: the
     * median width 6-12 px either way along `direction` 1.4 times the width at
     * the click or more, or the full width beyond a longer worn stretch
     * (wornBeyond()).
     */
    bool wornAtClick( const cv::Mat &grey, const LineProfile &profile, const LineHit &hit, const Eigen::Vector2d &direction )
    {
      LocateOptions either = locateOptionsFor( profile, FollowOptions(), 3.0 );
      either.maxWidthRatio = either.minWidthRatio = 2.5;
      std::vector<double> widths;
      for ( const double step : { -12.0, -6.0, 6.0, 12.0 } )
        if ( const std::optional<LineHit> h = locateLine( grey, hit.pixelInImage + step * direction, direction, profile, either ) )
          widths.push_back( h->widthPx );
      if ( widths.size() >= 2 )
      {
        std::nth_element( widths.begin(), widths.begin() + widths.size() / 2, widths.end() );
        if ( widths[widths.size() / 2] >= 1.4 * hit.widthPx )
          return true;
      }
      // worn over a longer stretch: the full width beyond it, 18-30 px along
      return wornBeyond( grey, hit.pixelInImage, direction, profile, hit.widthPx ).has_value();
    }

    /**
     * The line nearest the seed, looked for across `direction`; `support`
     * counts where it is found again along the direction (at +-6, 12, 18
     * and 24 px).
     */
    SeedAnalysis analyseAlong( const cv::Mat &grey, const Eigen::Vector2d &seedPixel, Eigen::Vector2d direction, const SeedOptions &options, int &support )
    {
      SeedAnalysis out;
      support = 0;
      LocateOptions locate;
      locate.searchHalfPx = options.searchRadiusPx;
      locate.minContrast = options.minContrast;
      locate.alongSamples = 5;
      struct Candidate
      {
        LineProfile profile;
        LineHit hit;
      };
      std::vector<Candidate> candidates;
      for ( const LineKind kind : { LineKind::BrightStripe, LineKind::DarkStripe } )
      {
        std::vector<Candidate> ofKind;
        locate.maxWidthRatio = locate.minWidthRatio = 1.5;
        for ( const double width : { 2.0, 3.0, 4.5, 6.5, 9.0, 13.0, 18.0, 25.0, 35.0, 50.0, 70.0 } )
        {
          if ( width > options.maxStripeWidthPx )
            break;
          LineProfile profile { kind, 1, width, 0.0 };
          if ( const std::optional<LineHit> hit = locateLine( grey, seedPixel, direction, profile, locate ) )
          {
            profile.widthPx = hit->widthPx;
            profile.contrast = hit->contrast;
            ofKind.push_back( Candidate { profile, *hit } );
          }
        }
        // of the stripes of a kind, the strongest; or one nearer the click with nearly its contrast (on
        // cobbles a narrow seam at the click and a wide dark patch of stones beside it are both found)
        if ( ofKind.empty() )
          continue;
        const Candidate *strongest = &*std::max_element( ofKind.begin(), ofKind.end(), []( const Candidate &a, const Candidate &b ) { return a.hit.contrast < b.hit.contrast; } );
        const Candidate *best = strongest;
        for ( const Candidate &c : ofKind )
          if ( c.hit.contrast >= 0.75 * strongest->hit.contrast && std::abs( c.hit.offsetPx ) < std::abs( best->hit.offsetPx ) - 1.0 )
            best = &c;
        candidates.push_back( *best );
      }
      locate.maxWidthRatio = locate.minWidthRatio = 2.2;
      for ( const int polarity : { 1, -1 } )
      {
        LineProfile profile { LineKind::Edge, polarity, 0.0, 0.0 };
        if ( const std::optional<LineHit> hit = locateLine( grey, seedPixel, direction, profile, locate ) )
        {
          profile.contrast = hit->contrast;
          candidates.push_back( { profile, *hit } );
        }
      }
      if ( candidates.empty() )
        {
          out.status = SeedAnalysis::Status::NoLine;
          out.message = "no edge or painted line within " + std::to_string( static_cast<int>( options.searchRadiusPx ) ) + " px of the seed";
          return out;
        }
      // the line nearest the click (a stripe by its centre, an edge by its step); a stripe wins a near tie
      const Candidate *chosen = nullptr;
      const auto better = [&]( const Candidate &c )
      {
        const double dc = std::abs( c.hit.offsetPx ), db = std::abs( chosen->hit.offsetPx );
        const bool cStripe = c.profile.kind != LineKind::Edge, bStripe = chosen->profile.kind != LineKind::Edge;
        if ( cStripe != bStripe && std::abs( dc - db ) <= 1.0 )
          return cStripe;
        return dc < db - 1e-9 || ( std::abs( dc - db ) <= 1e-9 && c.hit.contrast > chosen->hit.contrast );
      };
      // a click on worn paint means the stripe, not one of its sides: where the paint at the click is worn
      // to a part of its width (narrower there than along the line either side), the side of what is left can
      // lie nearer the click than its centre. (Elsewhere the nearest wins: a click at the foot of a kerb face,
      // a bright band of its own, means the edge.)
      const auto sideOfStripeAroundClick = [&]( const Candidate &edge )
      {
        return edge.profile.kind == LineKind::Edge &&
               std::any_of( candidates.begin(), candidates.end(), [&]( const Candidate &stripe )
        {
          if ( stripe.profile.kind == LineKind::Edge )
            return false;
          const double half = 0.5 * stripe.hit.widthPx;
          return std::abs( stripe.hit.offsetPx ) <= half + 1.0 && std::abs( std::abs( edge.hit.offsetPx - stripe.hit.offsetPx ) - half ) <= std::max( 2.0, 0.3 * half ) &&
                 wornAtClick( grey, stripe.profile, stripe.hit, direction );
        } );
      };
      for ( const Candidate &c : candidates )
        if ( !sideOfStripeAroundClick( c ) && ( !chosen || better( c ) ) )
          chosen = &c;
      if ( !chosen )
        chosen = &candidates.front();
      out.profile = chosen->profile;
      out.pixelInImage = chosen->hit.pixelInImage;

      // the direction measured along the line: the line located either side of the seed
      LocateOptions along = locateOptionsFor( out.profile, FollowOptions(), 3.0 );
      along.maxWidthRatio = along.minWidthRatio = 2.0;
      std::vector<Eigen::Vector2d> points { out.pixelInImage };
      std::vector<double> widths { out.profile.widthPx };
      for ( const double step : { -12.0, -6.0, 6.0, 12.0 } )
        if ( const std::optional<LineHit> h = locateLine( grey, out.pixelInImage + step * direction, direction, out.profile, along ) )
        {
          points.push_back( h->pixelInImage );
          widths.push_back( h->widthPx );
        }
      // a stripe's width from the profiles either side too: worn paint at the click narrows one profile
      if ( out.profile.kind != LineKind::Edge && widths.size() >= 3 )
      {
        std::nth_element( widths.begin(), widths.begin() + widths.size() / 2, widths.end() );
        out.profile.widthPx = widths[widths.size() / 2];
      }
      // paint worn to part of its width over the stretch either side too: the stripe's full width, and its
      // centre line at the click, from beyond the wear
      if ( out.profile.kind != LineKind::Edge )
        if ( const std::optional<WornStripe> worn = wornBeyond( grey, out.pixelInImage, direction, out.profile, out.profile.widthPx ) )
        {
          out.profile.widthPx = worn->widthPx;
          out.pixelInImage = worn->onCentreLine + worn->course.dot( out.pixelInImage - worn->onCentreLine ) * worn->course;
        }
      if ( points.size() >= 3 )
        if ( const std::optional<Eigen::Vector2d> measured = principalDirection( points ); measured && std::abs( measured->dot( direction ) ) > std::cos( 25.0 * kPi / 180.0 ) )
          direction = measured->dot( direction ) < 0 ? Eigen::Vector2d( -*measured ) : *measured; // (an edge's polarity is relative to the sense of travel, which is kept)

      out.direction = direction;
      out.status = SeedAnalysis::Status::Ok;
      // support: the line found again along the direction, on the course it sets; where it is found at
      // three or more of these, the direction from all of them (a crack or a notch near the click bends the
      // nearer ones)
      LocateOptions again = locateOptionsFor( out.profile, FollowOptions(), 2.5 );
      again.maxWidthRatio = again.minWidthRatio = 2.0;
      std::vector<Eigen::Vector2d> found { out.pixelInImage };
      for ( const double step : { -24.0, -18.0, -12.0, -6.0, 6.0, 12.0, 18.0, 24.0 } )
        if ( const std::optional<LineHit> h = locateLine( grey, out.pixelInImage + step * direction, direction, out.profile, again ) )
        {
          ++support;
          found.push_back( h->pixelInImage );
        }
      if ( support >= 3 )
        if ( const std::optional<Eigen::Vector2d> d = principalDirection( found ); d && std::abs( d->dot( direction ) ) > std::cos( 25.0 * kPi / 180.0 ) )
          out.direction = d->dot( direction ) < 0 ? Eigen::Vector2d( -*d ) : *d;
      return out;
    }
  }

  SeedAnalysis analyseSeed( const cv::Mat &grey, const Eigen::Vector2d &seedPixel, std::optional<double> directionDeg, const SeedOptions &options )
  {
    if ( grey.empty() || grey.type() != CV_8UC1 )
      throw std::invalid_argument( "analyseSeed needs an 8-bit grey image" );
    SeedAnalysis out;
    if ( !sampleGrey( grey, seedPixel ) )
    {
      out.status = SeedAnalysis::Status::OutsideImage;
      out.message = "the seed lies outside the image";
      return out;
    }
    Eigen::Vector2d direction;
    if ( directionDeg )
      direction = directionFromDegrees( *directionDeg );
    else if ( const std::optional<Eigen::Vector2d> d = tensorDirection( grey, seedPixel, options.directionWindow ) )
      direction = upOrRight( *d );
    else
      direction = Eigen::Vector2d( 0, -1 );

    int support = 0;
    out = analyseAlong( grey, seedPixel, direction, options, support );
    if ( !out.ok() )
      return out;
    // a line found across the direction measured at the click that is not found along it (a crack or a
    // worn notch across a stripe turns the measured direction): the direction a line of at least 70 % of
    // its contrast is found furthest along (not the texture of the road beside a short dash); a line found
    // at all 8 positions along a direction, with at least half the contrast (streaky gravel beside a weak
    // kerb edge turns the measured direction along its streaks, and its steps across them are stronger)
    const double contrast = out.profile.contrast;
    if ( !directionDeg && support < 6 )
      for ( int degrees = 0; degrees < 180; degrees += 15 )
      {
        int other = 0;
        const SeedAnalysis a = analyseAlong( grey, seedPixel, upOrRight( directionFromDegrees( degrees ) ), options, other );
        if ( a.ok() && other >= support + 2 && a.profile.contrast >= ( other == 8 ? 0.5 : 0.7 ) * contrast )
        {
          out = a;
          support = other;
        }
      }
    // a click on a crack or a worn patch across a stripe longer than those positions reach (no line at the
    // click is found at more than 3 of them): a line found beyond it, 12-24 px along a direction either way,
    // at 5 or more of the positions around there, that runs through the click - a stripe's middle 60 % or
    // within 2 px of an edge (not the side of a wide kerb face beside a weak edge clicked); the one nearest
    // the click (within 0.5 px: found furthest)
    if ( !directionDeg && support <= 3 )
    {
      std::optional<SeedAnalysis> beyond;
      int beyondSupport = 0;
      double beyondAcross = 0.0;
      for ( int degrees = 0; degrees < 180; degrees += 15 )
        for ( const double step : { -24.0, -18.0, -12.0, 12.0, 18.0, 24.0 } )
        {
          const Eigen::Vector2d along = upOrRight( directionFromDegrees( degrees ) );
          int other = 0;
          SeedAnalysis a = analyseAlong( grey, seedPixel + step * along, along, options, other );
          if ( !a.ok() || other < 5 || a.profile.contrast < 0.7 * contrast )
            continue;
          const double across = std::abs( rightNormal( a.direction ).dot( seedPixel - a.pixelInImage ) );
          const double reachPx = a.profile.kind == LineKind::Edge ? 2.0 : 0.3 * a.profile.widthPx;
          if ( across > reachPx || ( beyond && across > beyondAcross - 0.5 && ( across > beyondAcross + 0.5 || other <= beyondSupport ) ) )
            continue;
          a.pixelInImage += a.direction.dot( seedPixel - a.pixelInImage ) * a.direction;
          beyond = a;
          beyondSupport = other;
          beyondAcross = across;
        }
      if ( beyond )
        out = *beyond;
    }
    return out;
  }

} // namespace geostation
