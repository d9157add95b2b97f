/***************************************************************************
  crossprofile.cpp - grey-level profiles across a line object
 ***************************************************************************/
#include "extraction/crossprofile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace geostation
{

  void LineObjectOptions::check() const
  {
    if ( polarity < -1 || polarity > 1 )
      throw std::invalid_argument( "the polarity must be +1 (bright roads), -1 (dark roads) or 0 (either, side by side)" );
    if ( !( minContrast > 0.0 ) )
      throw std::invalid_argument( "the minimum contrast must be positive (grey levels)" );
    if ( !( maxVariation > 0.0 ) )
      throw std::invalid_argument( "the maximum variation must be positive (grey levels)" );
    if ( !( minWidthPx >= 1.0 ) || !( maxWidthPx >= minWidthPx ) || maxWidthPx > 200.0 )
      throw std::invalid_argument( "the road width must satisfy 1 <= minimum <= maximum <= 200 pixels, got " + std::to_string( minWidthPx ) + " .. " + std::to_string( maxWidthPx ) );
  }

  double greyAt( const cv::Mat &grey, double col, double row )
  {
    // pixelInImage: the centre of pixel (i, j) is (i + 0.5, j + 0.5)
    const double x = col - 0.5, y = row - 0.5;
    if ( !( x >= 0.0 ) || !( y >= 0.0 ) || x > grey.cols - 1 || y > grey.rows - 1 )
      return std::numeric_limits<double>::quiet_NaN();
    const int c0 = std::min( static_cast<int>( x ), std::max( 0, grey.cols - 2 ) );
    const int r0 = std::min( static_cast<int>( y ), std::max( 0, grey.rows - 2 ) );
    if ( grey.cols < 2 || grey.rows < 2 )
      return grey.at<uint8_t>( static_cast<int>( y ), static_cast<int>( x ) );
    const double fc = x - c0, fr = y - r0;
    const uint8_t *top = grey.ptr<uint8_t>( r0 ) + c0;
    const uint8_t *bottom = grey.ptr<uint8_t>( r0 + 1 ) + c0;
    return ( 1 - fr ) * ( ( 1 - fc ) * top[0] + fc * top[1] ) + fr * ( ( 1 - fc ) * bottom[0] + fc * bottom[1] );
  }

  std::vector<double> sampleCrossProfile( const cv::Mat &grey, const Eigen::Vector2d &centre, const Eigen::Vector2d &direction,
                                          int halfLength, int polarity, double alongHalfPx, int alongSamples )
  {
    const Eigen::Vector2d n = normalOf( direction );
    const int samples = std::max( 1, alongSamples );
    std::vector<double> profile( 2 * halfLength + 1 );
    for ( int t = -halfLength; t <= halfLength; ++t )
    {
      double sum = 0.0;
      for ( int k = 0; k < samples; ++k )
      {
        const double along = samples == 1 ? 0.0 : -alongHalfPx + 2.0 * alongHalfPx * k / ( samples - 1 );
        const Eigen::Vector2d p = centre + t * n + along * direction;
        sum += greyAt( grey, p.x(), p.y() );
      }
      profile[t + halfLength] = profileSign( polarity ) * sum / samples;
    }
    return profile;
  }

  namespace
  {
    //! Prefix sums of a profile with NaN bookkeeping.
    struct ProfileSums
    {
      std::vector<double> sum, sumSq;
      std::vector<int> invalid;

      explicit ProfileSums( const std::vector<double> &p )
        : sum( p.size() + 1, 0.0 ), sumSq( p.size() + 1, 0.0 ), invalid( p.size() + 1, 0 )
      {
        for ( size_t i = 0; i < p.size(); ++i )
        {
          const bool bad = std::isnan( p[i] );
          const double v = bad ? 0.0 : p[i];
          sum[i + 1] = sum[i] + v;
          sumSq[i + 1] = sumSq[i] + v * v;
          invalid[i + 1] = invalid[i] + ( bad ? 1 : 0 );
        }
      }
      bool valid( int a, int b ) const { return invalid[b] == invalid[a]; }
      double mean( int a, int b ) const { return ( sum[b] - sum[a] ) / ( b - a ); }
      double stdDev( int a, int b ) const
      {
        const double m = mean( a, b );
        return std::sqrt( std::max( 0.0, ( sumSq[b] - sumSq[a] ) / ( b - a ) - m * m ) );
      }
    };

    int flankOf( int width ) { return std::clamp( static_cast<int>( std::lround( 0.25 * width ) ), 2, 4 ); }

    //! The inside of a band starting at a, w wide, without its blurred first and last samples.
    int w0( int a, int w ) { return w >= 4 ? a + 1 : a; }
    int w1( int a, int w ) { return w >= 4 ? a + w - 1 : a + w; }

    double robustSpread( const std::vector<double> &p, int from, int to )
    {
      std::vector<double> v( p.begin() + from, p.begin() + to );
      if ( v.size() < 2 )
        return 0.0;
      std::nth_element( v.begin(), v.begin() + v.size() / 2, v.end() );
      const double median = v[v.size() / 2];
      for ( double &x : v )
        x = std::abs( x - median );
      std::nth_element( v.begin(), v.begin() + v.size() / 2, v.end() );
      return 1.4826 * v[v.size() / 2];
    }

    /**
     * A band between a darker and a brighter side must be a plateau, not
     * the ramp of a blurred edge between them (which has an inside between
     * its sides too): at least 3 samples, the inside's two halves within
     * 15 % of the contrast of each other.
     */
    bool isPlateau( const ProfileSums &sums, int a, int w, double contrast )
    {
      if ( w < 3 )
        return false;
      const int from = w0( a, w ), to = w1( a, w ), middle = ( from + to ) / 2;
      if ( to - from < 2 )
        return false;
      return std::abs( sums.mean( from, middle ) - sums.mean( middle, to ) ) <= 0.15 * contrast;
    }

    //! Where the profile crosses `level` between samples a and b (a < b or a > b), walking from a.
    std::optional<double> crossing( const std::vector<double> &p, int from, int to, double level )
    {
      const int step = to > from ? 1 : -1;
      for ( int i = from; i != to; i += step )
      {
        const double v0 = p[i], v1 = p[i + step];
        if ( std::isnan( v0 ) || std::isnan( v1 ) )
          continue;
        if ( ( v0 - level ) * ( v1 - level ) <= 0.0 && v0 != v1 )
          return i + step * ( level - v0 ) / ( v1 - v0 );
      }
      return std::nullopt;
    }
  } // namespace

  std::vector<CrossSection> findCrossSections( const std::vector<double> &profile, double widthMinPx, double widthMaxPx,
                                               double minContrast, double maxVariation, bool oneSided, int polarity )
  {
    struct Candidate
    {
      int a, w;
      double contrast, variation, score, inside, left, right;
      int tone;
    };
    const int n = static_cast<int>( profile.size() );
    const ProfileSums sums( profile );
    const bool eitherSign = polarity == 0;
    const int wMin = std::max( 1, static_cast<int>( std::floor( widthMinPx ) ) );
    const int wMax = std::max( wMin, static_cast<int>( std::ceil( widthMaxPx ) ) );
    std::vector<Candidate> candidates;
    constexpr int gap = 1; // blur between the band and its sides
    // widths 1 px apart up to 12 px, then about 6 % apart, and positions a sixteenth of the width apart:
    // the band's own width and centre come from its borders' half-contrast crossings below
    for ( int w = wMin; w <= wMax; w += std::max( 1, w / 16 ) )
    {
      const int f = flankOf( w );
      const int stride = std::max( 1, w / 16 );
      for ( int a = gap + f; a + w + gap + f <= n; a += stride )
      {
        if ( !sums.valid( a - gap - f, a + w + gap + f ) )
          continue;
        const double inside = sums.mean( a, a + w );
        const double left = sums.mean( a - gap - f, a - gap );
        const double right = sums.mean( a + w + gap, a + w + gap + f );
        double toLeft = inside - left, toRight = inside - right;
        // the band's tone in the image's grey levels (the profile carries the polarity's sign)
        const int tone = toLeft * toRight < 0.0 ? 0 : ( toLeft + toRight > 0.0 ? profileSign( polarity ) : -profileSign( polarity ) );
        bool mixed = false;
        if ( eitherSign )
        {
          mixed = toLeft * toRight < 0.0;
          toLeft = std::abs( toLeft );
          toRight = std::abs( toRight );
        }
        double contrast = std::min( toLeft, toRight );
        if ( oneSided && ( contrast >= -minContrast / 3.0 || mixed ) )
          contrast = std::max( toLeft, toRight );
        if ( contrast < minContrast )
          continue;
        if ( mixed && !( oneSided || isPlateau( sums, a, w, contrast ) ) )
          continue;
        // a cheap first look: markings and cars inside a road inflate the standard deviation, so allow twice the limit here
        const double variation = w >= 4 ? sums.stdDev( a + 1, a + w - 1 ) : w >= 2 ? sums.stdDev( a, a + w ) : 0.0;
        if ( variation > 2.0 * maxVariation )
          continue;
        candidates.push_back( { a, w, contrast, variation, contrast - 0.5 * variation, inside, left, right, tone } );
      }
    }
    std::sort( candidates.begin(), candidates.end(), []( const Candidate &x, const Candidate &y ) { return x.score > y.score; } );
    std::vector<CrossSection> found;
    std::vector<std::pair<double, double>> taken; // centre, width
    const double origin = 0.5 * ( n - 1 );
    for ( const Candidate &c : candidates )
    {
      const double centre = c.a + 0.5 * ( c.w - 1 );
      bool overlaps = false;
      for ( const auto &[tc, tw] : taken )
        overlaps = overlaps || std::abs( centre - tc ) < 0.5 * std::max<double>( tw, c.w ) + 1.0;
      if ( overlaps )
        continue;
      // the uniformity test proper: a robust spread (1.4826 x the median absolute deviation), indifferent to a few bright or dark pixels
      const double spread = robustSpread( profile, w0( c.a, c.w ), w1( c.a, c.w ) );
      if ( spread > maxVariation )
        continue;
      taken.emplace_back( centre, c.w );
      const int f = flankOf( c.w );
      const std::optional<double> leftEdge = crossing( profile, std::max( 0, c.a - gap - f / 2 ), std::min( n - 1, c.a + c.w / 2 ), 0.5 * ( c.inside + c.left ) );
      const std::optional<double> rightEdge = crossing( profile, std::min( n - 1, c.a + c.w - 1 + gap + f / 2 ), std::max( 0, c.a + c.w / 2 ), 0.5 * ( c.inside + c.right ) );
      const double l = leftEdge ? *leftEdge : c.a - 0.5;
      const double r = rightEdge ? *rightEdge : c.a + c.w - 0.5;
      CrossSection s;
      s.offsetPx = ( r > l ? 0.5 * ( l + r ) : centre ) - origin;
      s.widthPx = r > l ? r - l : c.w;
      s.contrast = c.contrast;
      s.variation = robustSpread( profile, w0( c.a, c.w ), w1( c.a, c.w ) );
      s.tone = c.tone;
      found.push_back( s );
    }
    return found;
  }

  std::vector<double> bandResponse( const std::vector<double> &profile, double widthPx, int polarity )
  {
    const int n = static_cast<int>( profile.size() );
    const int half = std::max( 1, static_cast<int>( std::lround( 0.5 * ( widthPx - 1 ) ) ) );
    const int w = 2 * half + 1;
    const int f = flankOf( w );
    constexpr int gap = 1;
    const ProfileSums sums( profile );
    std::vector<double> response( n, std::numeric_limits<double>::quiet_NaN() );
    for ( int i = half + gap + f; i + half + gap + f < n; ++i )
    {
      const int a = i - half;
      if ( !sums.valid( a - gap - f, a + w + gap + f ) )
        continue;
      const double inside = sums.mean( a, a + w );
      const double toLeft = inside - sums.mean( a - gap - f, a - gap ), toRight = inside - sums.mean( a + w + gap, a + w + gap + f );
      response[i] = polarity != 0 ? std::min( toLeft, toRight ) : toLeft * toRight > 0.0 ? std::min( std::abs( toLeft ), std::abs( toRight ) ) : 0.0;
    }
    return response;
  }

} // namespace geostation
