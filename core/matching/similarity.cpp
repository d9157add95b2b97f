/***************************************************************************
  similarity.cpp - cc, ncc, wcc, wncc and the parabola peak
 ***************************************************************************/
#include "matching/similarity.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <opencv2/imgproc.hpp>

#ifdef __SSE2__
#include <emmintrin.h>
#endif
#if defined( __x86_64__ ) && defined( __GNUC__ )
#include <immintrin.h>
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

  namespace
  {
    bool oddWindow( int width, int height )
    {
      return width >= 1 && height >= 1 && width % 2 == 1 && height % 2 == 1 && width * height <= 101 * 101;
    }
    const char *const kBadWindow = "the window must have odd sizes, at most 101 x 101 pixels";
  }

  CorrelationTemplate::CorrelationTemplate( const MatchImage &image, int centreCol, int centreRow, int width, int height, SimilarityMeasure measure )
    : mWidth( width ), mHeight( height ), mMeasure( measure )
  {
    if ( !oddWindow( width, height ) )
    {
      mReason = kBadWindow;
      return;
    }
    const int c0 = centreCol - width / 2, r0 = centreRow - height / 2;
    if ( !image.holds( cv::Rect( c0, r0, width, height ) ) )
    {
      mReason = "the window leaves the reference image";
      return;
    }
    std::vector<int> values( static_cast<size_t>( width ) * height );
    for ( int r = 0; r < height; ++r )
      std::copy( image.greyAt( c0, r0 + r ), image.greyAt( c0, r0 + r ) + width, values.begin() + static_cast<size_t>( r ) * width );
    setValues( std::move( values ) );
  }

  CorrelationTemplate::CorrelationTemplate( const MatchImage &image, const Eigen::Vector2d &pixelInImage, const Eigen::Matrix2d &imageFromWindow,
      int width, int height, SimilarityMeasure measure )
    : mWidth( width ), mHeight( height ), mMeasure( measure )
  {
    if ( !oddWindow( width, height ) )
    {
      mReason = kBadWindow;
      return;
    }
    // each template pixel integrates its footprint in the image (n x n samples), as a sensor pixel does:
    // a template that shrinks the image's patch does not alias its detail
    const double footprint = std::max( imageFromWindow.col( 0 ).norm(), imageFromWindow.col( 1 ).norm() );
    const int n = std::clamp( static_cast<int>( std::ceil( footprint ) ), 1, 4 );
    std::vector<int> values( static_cast<size_t>( width ) * height );
    for ( int r = 0; r < height; ++r )
      for ( int c = 0; c < width; ++c )
      {
        double sum = 0.0;
        for ( int i = 0; i < n; ++i )
          for ( int j = 0; j < n; ++j )
          {
            const Eigen::Vector2d offset( c - width / 2 + ( i + 0.5 ) / n - 0.5, r - height / 2 + ( j + 0.5 ) / n - 0.5 );
            const Eigen::Vector2d at = pixelInImage + imageFromWindow * offset;
            if ( !image.canSampleCubic( at.x(), at.y() ) )
            {
              mReason = "the window leaves the reference image";
              return;
            }
            sum += image.sampleBilinear( at.x(), at.y() );
          }
        values[static_cast<size_t>( r ) * width + c] = std::clamp( static_cast<int>( std::lround( sum / ( n * n ) ) ), 0, 255 );
      }
    setValues( std::move( values ) );
  }

  void CorrelationTemplate::setValues( std::vector<int> values )
  {
    const int width = mWidth, height = mHeight;
    const SimilarityMeasure measure = mMeasure;
    const bool weighted = measure == SimilarityMeasure::WCC || measure == SimilarityMeasure::WNCC;
    mPaddedWidth = ( width + 15 ) / 16 * 16;
    mPadded.assign( static_cast<size_t>( mPaddedWidth ) * height, 0 );
    mMask.assign( mPaddedWidth, 0 );
    std::fill( mMask.begin(), mMask.begin() + width, static_cast<int16_t>( -1 ) );
    mValues = std::move( values );
    int64_t plainSum = 0, plainSq = 0;
    for ( int r = 0; r < height; ++r )
    {
      const int *row = mValues.data() + static_cast<size_t>( r ) * width;
      int16_t *padded = mPadded.data() + static_cast<size_t>( r ) * mPaddedWidth;
      for ( int c = 0; c < width; ++c )
      {
        const int v = row[c];
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
    {
      mReason = "the window is flat (no texture to correlate)";
      mFlat = true;
    }
  }

  std::optional<double> CorrelationTemplate::score( const MatchImage &search, int centreCol, int centreRow ) const
  {
    const int c0 = centreCol - mWidth / 2, r0 = centreRow - mHeight / 2;
    if ( !valid() || !search.holds( cv::Rect( c0, r0, mWidth, mHeight ) ) )
      return std::nullopt;
    if ( mMeasure == SimilarityMeasure::CC || mMeasure == SimilarityMeasure::NCC )
    {
      // integer sums: exact; rows padded to 16 so the compiler vectorises them
      int64_t st = 0, s = 0, ss = 0;
      // (the padded rows are read whole: they must lie in the pixels held)
      if ( c0 - search.origin().x + mPaddedWidth <= search.grey().cols )
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
            const __m128i v = _mm_loadu_si128( reinterpret_cast<const __m128i *>( search.greyAt( c0 + c, r0 + r ) ) );
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
          const uint8_t *row = search.greyAt( c0, r0 + r );
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
          const uint8_t *row = search.greyAt( c0, r0 + r );
          for ( int c = 0; c < mWidth; ++c )
          {
            const int32_t v = row[c];
            st += t[c] * v;
            s += v;
            ss += v * v;
          }
        }
      }
      return integerScore( st, s, ss );
    }
    // weighted measures
    double st = 0, s = 0, ss = 0;
    const int *t = mValues.data();
    const double *w = mWeights.data();
    for ( int r = 0; r < mHeight; ++r, t += mWidth, w += mWidth )
    {
      const uint8_t *row = search.greyAt( c0, r0 + r );
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

  std::optional<double> CorrelationTemplate::integerScore( int64_t st, int64_t s, int64_t ss ) const
  {
    const double n = static_cast<double>( mWidth ) * mHeight;
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

  namespace
  {
#if defined( __x86_64__ ) && defined( __GNUC__ )
    __attribute__( ( target( "avx2" ) ) ) int64_t reduce( __m256i acc )
    {
      const __m128i half = _mm_add_epi32( _mm256_castsi256_si128( acc ), _mm256_extracti128_si256( acc, 1 ) );
      const __m128i pairs = _mm_add_epi32( half, _mm_shuffle_epi32( half, _MM_SHUFFLE( 1, 0, 3, 2 ) ) );
      return _mm_cvtsi128_si32( _mm_add_epi32( pairs, _mm_shuffle_epi32( pairs, _MM_SHUFFLE( 2, 3, 0, 1 ) ) ) );
    }

    //! AVX2: one multiply-add instruction per 16 template pixels (chosen at run time, where the CPU has it).
    __attribute__( ( target( "avx2" ) ) )
    void crossTermsAvx2( const int16_t *area, size_t step, const int16_t *padded, int paddedWidth, int height, int count, int64_t *out )
    {
      int c = 0;
      // four neighbouring positions at a time: they share the template rows and keep four sums in flight
      for ( ; c + 3 < count; c += 4 )
      {
        __m256i acc0 = _mm256_setzero_si256(), acc1 = _mm256_setzero_si256(), acc2 = _mm256_setzero_si256(), acc3 = _mm256_setzero_si256();
        const int16_t *t = padded, *row = area + c;
        for ( int wr = 0; wr < height; ++wr, t += paddedWidth, row += step )
          for ( int k = 0; k < paddedWidth; k += 16 )
          {
            const __m256i tk = _mm256_loadu_si256( reinterpret_cast<const __m256i *>( t + k ) );
            acc0 = _mm256_add_epi32( acc0, _mm256_madd_epi16( _mm256_loadu_si256( reinterpret_cast<const __m256i *>( row + k ) ), tk ) );
            acc1 = _mm256_add_epi32( acc1, _mm256_madd_epi16( _mm256_loadu_si256( reinterpret_cast<const __m256i *>( row + k + 1 ) ), tk ) );
            acc2 = _mm256_add_epi32( acc2, _mm256_madd_epi16( _mm256_loadu_si256( reinterpret_cast<const __m256i *>( row + k + 2 ) ), tk ) );
            acc3 = _mm256_add_epi32( acc3, _mm256_madd_epi16( _mm256_loadu_si256( reinterpret_cast<const __m256i *>( row + k + 3 ) ), tk ) );
          }
        out[c] = reduce( acc0 );
        out[c + 1] = reduce( acc1 );
        out[c + 2] = reduce( acc2 );
        out[c + 3] = reduce( acc3 );
      }
      for ( ; c < count; ++c )
      {
        __m256i acc = _mm256_setzero_si256();
        const int16_t *t = padded, *row = area + c;
        for ( int wr = 0; wr < height; ++wr, t += paddedWidth, row += step )
          for ( int k = 0; k < paddedWidth; k += 16 )
            acc = _mm256_add_epi32( acc, _mm256_madd_epi16( _mm256_loadu_si256( reinterpret_cast<const __m256i *>( row + k ) ),
                                    _mm256_loadu_si256( reinterpret_cast<const __m256i *>( t + k ) ) ) );
        out[c] = reduce( acc );
      }
    }

    bool cpuHasAvx2()
    {
      static const bool has = __builtin_cpu_supports( "avx2" );
      return has;
    }
#endif

    /**
     * The cross terms sum(t * s) of the windows starting at columns 0..count-1
     * of a row of `area` (16-bit copy of the search pixels, `step` values per
     * row, padded on the right so that whole padded template rows can be
     * read; the template's padding is 0).
     */
    void crossTermsOfRow( const int16_t *area, size_t step, const int16_t *padded, int paddedWidth, int height, int count, int64_t *out )
    {
#if defined( __x86_64__ ) && defined( __GNUC__ )
      if ( cpuHasAvx2() )
      {
        crossTermsAvx2( area, step, padded, paddedWidth, height, count, out );
        return;
      }
#endif
#ifdef __SSE2__
      for ( int c = 0; c < count; ++c )
      {
        __m128i acc = _mm_setzero_si128();
        const int16_t *t = padded, *row = area + c;
        for ( int wr = 0; wr < height; ++wr, t += paddedWidth, row += step )
          for ( int k = 0; k < paddedWidth; k += 8 )
            acc = _mm_add_epi32( acc, _mm_madd_epi16( _mm_loadu_si128( reinterpret_cast<const __m128i *>( row + k ) ),
                                 _mm_loadu_si128( reinterpret_cast<const __m128i *>( t + k ) ) ) );
        alignas( 16 ) int32_t lanes[4];
        _mm_store_si128( reinterpret_cast<__m128i *>( lanes ), acc );
        out[c] = static_cast<int64_t>( lanes[0] ) + lanes[1] + lanes[2] + lanes[3];
      }
#else
      for ( int c = 0; c < count; ++c )
      {
        int64_t st = 0;
        const int16_t *t = padded, *row = area + c;
        for ( int wr = 0; wr < height; ++wr, t += paddedWidth, row += step )
          for ( int k = 0; k < paddedWidth; ++k )
            st += static_cast<int32_t>( t[k] ) * row[k];
        out[c] = st;
      }
#endif
    }
  }

  cv::Mat CorrelationTemplate::scoreArea( const MatchImage &search, const cv::Rect &centres ) const
  {
    cv::Mat scores( centres.height, centres.width, CV_64F );
    if ( !valid() || centres.empty() )
      return scores.setTo( std::numeric_limits<double>::quiet_NaN() );
    const cv::Mat &grey = search.grey();
    const int halfW = mWidth / 2, halfH = mHeight / 2;
    if ( mMeasure == SimilarityMeasure::WCC || mMeasure == SimilarityMeasure::WNCC )
    {
      for ( int r = 0; r < centres.height; ++r )
        for ( int c = 0; c < centres.width; ++c )
          scores.at<double>( r, c ) = score( search, centres.x + c, centres.y + r ).value_or( std::numeric_limits<double>::quiet_NaN() );
      return scores;
    }
    // the centres whose windows lie in the image
    const cv::Rect &offered = search.offered();
    const cv::Rect valid = centres & cv::Rect( offered.x + halfW, offered.y + halfH, offered.width - mWidth + 1, offered.height - mHeight + 1 );
    if ( valid != centres )
      scores.setTo( std::numeric_limits<double>::quiet_NaN() ); // the centres without a whole window
    if ( valid.empty() )
      return scores;
    // window sums from integral images of the pixels the windows cover
    const cv::Rect covered( valid.x - halfW, valid.y - halfH, valid.width + mWidth - 1, valid.height + mHeight - 1 );
    cv::Mat sum, sqsum;
    const cv::Mat coveredGrey = grey( covered - search.origin() );
    cv::integral( coveredGrey, sum, sqsum, CV_32S, CV_64F );
    // a 16-bit copy of the covered pixels, padded on the right for whole template rows
    cv::Mat area( covered.height, covered.width + mPaddedWidth - mWidth, CV_16S );
    area.colRange( covered.width, area.cols ).setTo( 0 );
    coveredGrey.convertTo( area.colRange( 0, covered.width ), CV_16S );
    const size_t areaStep = area.step[0] / sizeof( int16_t );
    std::vector<int64_t> crossTerms( valid.width );
    const double n = static_cast<double>( mWidth ) * mHeight;
    const double meanT = mSum / n, templateVariance = mSumSq - mSum * mSum / n;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for ( int r = 0; r < valid.height; ++r )
    {
      crossTermsOfRow( area.ptr<int16_t>( r ), areaStep, mPadded.data(), mPaddedWidth, mHeight, valid.width, crossTerms.data() );
      double *out = scores.ptr<double>( valid.y - centres.y + r ) + ( valid.x - centres.x );
      const int *sTop = sum.ptr<int>( r ), *sBottom = sum.ptr<int>( r + mHeight );
      const double *qTop = sqsum.ptr<double>( r ), *qBottom = sqsum.ptr<double>( r + mHeight );
      // the same formulas as integerScore(), branch-free so the loop vectorises
      if ( mMeasure == SimilarityMeasure::CC )
        for ( int c = 0; c < valid.width; ++c )
        {
          const double ss = qBottom[c + mWidth] - qBottom[c] - qTop[c + mWidth] + qTop[c];
          const double denominator = std::sqrt( mSumSq * ss );
          out[c] = denominator > 0.0 ? static_cast<double>( crossTerms[c] ) / denominator : nan;
        }
      else
        for ( int c = 0; c < valid.width; ++c )
        {
          const double s = static_cast<double>( sBottom[c + mWidth] - sBottom[c] - sTop[c + mWidth] + sTop[c] );
          const double ss = qBottom[c + mWidth] - qBottom[c] - qTop[c + mWidth] + qTop[c];
          const double covariance = static_cast<double>( crossTerms[c] ) - meanT * s;
          const double searchVariance = ss - s * s / n;
          out[c] = searchVariance < 0.25 * n ? nan : covariance / std::sqrt( templateVariance * searchVariance );
        }
    }
    return scores;
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
