/***************************************************************************
  similarity.cpp - cc, ncc, wcc, wncc and the parabola peak
 ***************************************************************************/
#include "matching/similarity.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace geostation
{

  std::string similarityMeasureName( SimilarityMeasure measure )
  {
    switch ( measure )
    {
      case SimilarityMeasure::CC:
        return "cc";
      case SimilarityMeasure::NCC:
        return "ncc";
      case SimilarityMeasure::WCC:
        return "wcc";
      case SimilarityMeasure::WNCC:
        return "wncc";
    }
    return "ncc";
  }

  std::optional<SimilarityMeasure> similarityMeasureFromName( const std::string &name )
  {
    for ( SimilarityMeasure m : { SimilarityMeasure::CC, SimilarityMeasure::NCC, SimilarityMeasure::WCC, SimilarityMeasure::WNCC } )
      if ( similarityMeasureName( m ) == name )
        return m;
    return std::nullopt;
  }

  double centreWeight( int dx, int dy, int width, int height )
  {
    const double hx = std::max( 1, width / 2 ), hy = std::max( 1, height / 2 );
    const double r = std::min( 1.0, std::max( width > 1 ? std::abs( dx ) / hx : 0.0, height > 1 ? std::abs( dy ) / hy : 0.0 ) );
    return 2.0 + 3.0 * ( 1.0 - r ) * ( 1.0 - r );
  }

  CorrelationTemplate::CorrelationTemplate( const MatchImage &image, int centreCol, int centreRow, int width, int height, SimilarityMeasure measure )
    : mWidth( width ), mHeight( height ), mMeasure( measure )
  {
    if ( width < 1 || height < 1 || width % 2 == 0 || height % 2 == 0 || width * height > 101 * 101 )
    {
      mReason = "the window must have odd sizes, at most 101 x 101 pixels";
      return;
    }
    const int c0 = centreCol - width / 2, r0 = centreRow - height / 2;
    if ( c0 < 0 || r0 < 0 || c0 + width > image.width() || r0 + height > image.height() )
    {
      mReason = "the window leaves the reference image";
      return;
    }
    const bool weighted = measure == SimilarityMeasure::WCC || measure == SimilarityMeasure::WNCC;
    mPaddedWidth = ( width + 15 ) / 16 * 16;
    mPadded.assign( static_cast<size_t>( mPaddedWidth ) * height, 0 );
    mMask.assign( mPaddedWidth, 0 );
    std::fill( mMask.begin(), mMask.begin() + width, static_cast<int16_t>( -1 ) );
    mValues.resize( static_cast<size_t>( width ) * height );
    int64_t plainSum = 0, plainSq = 0;
    for ( int r = 0; r < height; ++r )
    {
      const uint8_t *row = image.grey().ptr<uint8_t>( r0 + r ) + c0;
      int *values = mValues.data() + static_cast<size_t>( r ) * width;
      int16_t *padded = mPadded.data() + static_cast<size_t>( r ) * mPaddedWidth;
      for ( int c = 0; c < width; ++c )
      {
        const int v = row[c];
        values[c] = v;
        padded[c] = static_cast<int16_t>( v );
        plainSum += v;
        plainSq += v * v;
      }
    }
    if ( weighted )
    {
      mWeights.reserve( mValues.size() );
      for ( int r = 0; r < height; ++r )
        for ( int c = 0; c < width; ++c )
        {
          const double w = centreWeight( c - width / 2, r - height / 2, width, height );
          const double v = mValues[static_cast<size_t>( r ) * width + c];
          mWeights.push_back( w );
          mWeightSum += w;
          mSum += w * v;
          mSumSq += w * v * v;
        }
    }
    else
    {
      mWeightSum = static_cast<double>( width ) * height;
      mSum = static_cast<double>( plainSum );
      mSumSq = static_cast<double>( plainSq );
    }
    const double n = static_cast<double>( width ) * height;
    mContrast = std::sqrt( std::max( 0.0, static_cast<double>( plainSq ) / n - ( static_cast<double>( plainSum ) / n ) * ( static_cast<double>( plainSum ) / n ) ) );
    const bool normalised = measure == SimilarityMeasure::NCC || measure == SimilarityMeasure::WNCC;
    if ( ( normalised && mContrast < 0.5 ) || ( !normalised && mSumSq <= 0.0 ) )
      mReason = "the window is flat (no texture to correlate)";
  }

  std::optional<double> CorrelationTemplate::score( const MatchImage &search, int centreCol, int centreRow ) const
  {
    const int c0 = centreCol - mWidth / 2, r0 = centreRow - mHeight / 2;
    if ( !valid() || c0 < 0 || r0 < 0 || c0 + mWidth > search.width() || r0 + mHeight > search.height() )
      return std::nullopt;
    const double n = static_cast<double>( mWidth ) * mHeight;
    if ( mMeasure == SimilarityMeasure::CC || mMeasure == SimilarityMeasure::NCC )
    {
      // integer sums: exact; rows padded to 16 so the compiler vectorises them
      int64_t st = 0, s = 0, ss = 0;
      if ( c0 + mPaddedWidth <= search.grey().cols )
      {
#ifdef __SSE2__
        // 16 pixels at a time: pmaddwd does eight multiply-adds into four 32-bit sums
        __m128i accSt = _mm_setzero_si128(), accS = _mm_setzero_si128(), accSs = _mm_setzero_si128();
        const __m128i zero = _mm_setzero_si128(), ones = _mm_set1_epi16( 1 );
        for ( int c = 0; c < mPaddedWidth; c += 16 )
        {
          // the window's pixels only: the mask keeps the window's columns and clears the padding
          const __m128i maskLo = _mm_loadu_si128( reinterpret_cast<const __m128i *>( mMask.data() + c ) );
          const __m128i maskHi = _mm_loadu_si128( reinterpret_cast<const __m128i *>( mMask.data() + c + 8 ) );
          const int16_t *t = mPadded.data() + c;
          for ( int r = 0; r < mHeight; ++r, t += mPaddedWidth )
          {
            const __m128i v = _mm_loadu_si128( reinterpret_cast<const __m128i *>( search.grey().ptr<uint8_t>( r0 + r ) + c0 + c ) );
            const __m128i lo = _mm_and_si128( _mm_unpacklo_epi8( v, zero ), maskLo ), hi = _mm_and_si128( _mm_unpackhi_epi8( v, zero ), maskHi );
            const __m128i tlo = _mm_loadu_si128( reinterpret_cast<const __m128i *>( t ) ), thi = _mm_loadu_si128( reinterpret_cast<const __m128i *>( t + 8 ) );
            accSt = _mm_add_epi32( accSt, _mm_add_epi32( _mm_madd_epi16( lo, tlo ), _mm_madd_epi16( hi, thi ) ) );
            accS = _mm_add_epi32( accS, _mm_add_epi32( _mm_madd_epi16( lo, ones ), _mm_madd_epi16( hi, ones ) ) );
            accSs = _mm_add_epi32( accSs, _mm_add_epi32( _mm_madd_epi16( lo, lo ), _mm_madd_epi16( hi, hi ) ) );
          }
        }
        alignas( 16 ) int32_t lanes[3][4];
        _mm_store_si128( reinterpret_cast<__m128i *>( lanes[0] ), accSt );
        _mm_store_si128( reinterpret_cast<__m128i *>( lanes[1] ), accS );
        _mm_store_si128( reinterpret_cast<__m128i *>( lanes[2] ), accSs );
        for ( int k = 0; k < 4; ++k )
        {
          st += lanes[0][k];
          s += lanes[1][k];
          ss += lanes[2][k];
        }
#else
        // the padding columns are summed too (the template is 0 there) and taken off afterwards
        const int16_t *t = mPadded.data();
        for ( int r = 0; r < mHeight; ++r, t += mPaddedWidth )
        {
          const uint8_t *row = search.grey().ptr<uint8_t>( r0 + r ) + c0;
          int32_t rowSt = 0, rowS = 0, rowSs = 0;
          for ( int c = 0; c < mPaddedWidth; ++c )
          {
            const int16_t v = row[c];
            rowSt += static_cast<int32_t>( t[c] ) * static_cast<int32_t>( v );
            rowS += v;
            rowSs += static_cast<int32_t>( v ) * static_cast<int32_t>( v );
          }
          for ( int c = mWidth; c < mPaddedWidth; ++c )
          {
            rowS -= row[c];
            rowSs -= static_cast<int32_t>( row[c] ) * row[c];
          }
          st += rowSt;
          s += rowS;
          ss += rowSs;
        }
#endif
      }
      else
      {
        const int *t = mValues.data();
        for ( int r = 0; r < mHeight; ++r, t += mWidth )
        {
          const uint8_t *row = search.grey().ptr<uint8_t>( r0 + r ) + c0;
          for ( int c = 0; c < mWidth; ++c )
          {
            const int32_t v = row[c];
            st += t[c] * v;
            s += v;
            ss += v * v;
          }
        }
      }
      if ( mMeasure == SimilarityMeasure::CC )
      {
        const double denominator = std::sqrt( mSumSq * static_cast<double>( ss ) );
        return denominator > 0.0 ? std::optional<double>( st / denominator ) : std::nullopt;
      }
      const double covariance = st - mSum * s / n;
      const double searchVariance = ss - static_cast<double>( s ) * s / n;
      const double templateVariance = mSumSq - mSum * mSum / n;
      if ( searchVariance < 0.25 * n )
        return std::nullopt; // flat search window
      return covariance / std::sqrt( templateVariance * searchVariance );
    }
    // weighted measures
    double st = 0, s = 0, ss = 0;
    const int *t = mValues.data();
    const double *w = mWeights.data();
    for ( int r = 0; r < mHeight; ++r, t += mWidth, w += mWidth )
    {
      const uint8_t *row = search.grey().ptr<uint8_t>( r0 + r ) + c0;
      for ( int c = 0; c < mWidth; ++c )
      {
        const double v = row[c];
        st += w[c] * t[c] * v;
        s += w[c] * v;
        ss += w[c] * v * v;
      }
    }
    if ( mMeasure == SimilarityMeasure::WCC )
    {
      const double denominator = std::sqrt( mSumSq * ss );
      return denominator > 0.0 ? std::optional<double>( st / denominator ) : std::nullopt;
    }
    const double covariance = st - mSum * s / mWeightSum;
    const double searchVariance = ss - s * s / mWeightSum;
    const double templateVariance = mSumSq - mSum * mSum / mWeightSum;
    if ( searchVariance < 0.25 * mWeightSum )
      return std::nullopt;
    return covariance / std::sqrt( templateVariance * searchVariance );
  }

  double parabolaPeakOffset( double before, double at, double after )
  {
    // f = a0 + a1 x + a2 x^2 through (-1, before), (0, at), (1, after); x = -a1 / (2 a2)
    const double a1 = 0.5 * ( after - before ), a2 = 0.5 * ( after + before ) - at;
    if ( !( a2 < 0.0 ) )
      return 0.0;
    return std::clamp( -a1 / ( 2.0 * a2 ), -0.5, 0.5 );
  }

} // namespace geostation
