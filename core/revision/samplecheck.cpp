/***************************************************************************
  samplecheck.cpp - one place along a map road, checked in both images
 ***************************************************************************/
#include "revision/samplecheck.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace geostation::revision
{
  namespace
  {
    //! a band this much wider than the one a moved sample settled on, touching it, is the road it borders
    constexpr double kRoadOverVerge = 1.3;
    //! bands whose edges lie this close count as touching
    constexpr double kTouchingPx = 2.0;
    //! neighbours of a moved sample where a car or a shadow hides the road's band but not its verge
    constexpr int kSupportLostToCars = 2;
    //! the verges either side of a road: widths within this share of each other
    constexpr double kTwinWidthShare = 0.4;

    bool touching( const Sample::Candidate &a, const Sample::Candidate &b )
    {
      return std::abs( a.offsetPx - b.offsetPx ) <= 0.5 * ( a.widthPx + b.widthPx ) + kTouchingPx;
    }

    //! A band like `verge` touching `road` on its other side.
    bool hasTwinBeyond( const std::vector<Sample::Candidate> &candidates, const Sample::Candidate &road, const Sample::Candidate &verge )
    {
      const double side = verge.offsetPx < road.offsetPx ? -1.0 : 1.0;
      return std::any_of( candidates.begin(), candidates.end(), [&]( const Sample::Candidate &t ) {
        return ( t.offsetPx - road.offsetPx ) * side < 0.0 && touching( t, road ) &&
               std::abs( t.widthPx - verge.widthPx ) <= kTwinWidthShare * std::max( t.widthPx, verge.widthPx );
      } );
    }
  } // namespace

  bool inFrame( const OrientedImage &image, const Eigen::Vector3d &ground, Eigen::Vector2d &pixel, double marginPx )
  {
    const GroundProjection p = image.projectGroundToPixel( ground );
    pixel = p.pixelInImage;
    return p.ok() && pixel.x() > marginPx && pixel.y() > marginPx && pixel.x() < image.camera().width - marginPx && pixel.y() < image.camera().height - marginPx;
  }

  //! The bands across `along` at `at` within `searchPx` of it, nearest first (offsets along the normal of `along`).
  bool hiddenFrom( const OrientedImage &image, const Eigen::Vector3d &ground,
                   const std::function<std::optional<Eigen::Vector3d>( const Ray & )> &surface, double clearanceM )
  {
    const Eigen::Vector3d centre = image.exterior().projectionCentre;
    const Eigen::Vector3d towards = ground - centre;
    if ( !( towards.norm() > 0.0 ) )
      return false;
    const std::optional<Eigen::Vector3d> hit = surface( Ray { centre, towards.normalized() } );
    return hit && hit->z() > ground.z() + clearanceM;
  }

  std::vector<CrossSection> bandsNear( const GreyTiles &grey, const Eigen::Vector2d &at, const Eigen::Vector2d &along, const LineObjectOptions &object, double searchPx,
                                       double alongHalfPx, bool oneSided )
  {
    const int half = static_cast<int>( std::ceil( searchPx + object.maxWidthPx ) ) + 6;
    // the profile's corners: half across, alongHalfPx along
    const GreyWindow window = grey.around( at, static_cast<int>( std::ceil( std::hypot( half, alongHalfPx ) ) ) + 4 );
    // samples along about 2 px apart, at least three
    const int alongSamples = std::max( 3, 2 * static_cast<int>( std::ceil( 0.5 * alongHalfPx ) ) + 1 );
    const std::vector<double> profile = sampleCrossProfile( window.pixels, window.toWindow( at ), along, half, object.polarity, alongHalfPx, alongSamples );
    std::vector<CrossSection> bands;
    for ( const CrossSection &s : findCrossSections( profile, object.minWidthPx, object.maxWidthPx, object.minContrast, object.maxVariation, oneSided, object.polarity ) )
      if ( std::abs( s.offsetPx ) <= searchPx )
        bands.push_back( s );
    std::sort( bands.begin(), bands.end(), []( const CrossSection &x, const CrossSection &y ) { return std::abs( x.offsetPx ) < std::abs( y.offsetPx ); } );
    return bands;
  }

  Eigen::Vector2d directionAt( const std::vector<Sample> &samples, size_t i, bool inA )
  {
    const size_t from = i > 0 ? i - 1 : 0, to = std::min( i + 1, samples.size() - 1 );
    const Eigen::Vector2d d = inA ? samples[to].inA - samples[from].inA : samples[to].inB - samples[from].inB;
    return d.norm() > 1e-9 ? Eigen::Vector2d( d.normalized() ) : Eigen::Vector2d::UnitX();
  }

  namespace
  {
    //! A band on the mapped course in both images, the profiles averaged over `alongHalfPx` along it: the sample confirmed.
    bool confirmOnCourse( Sample &s, const Eigen::Vector2d &alongA, const Eigen::Vector2d &alongB, const PairView &pair, double alongHalfPx )
    {
      const std::vector<CrossSection> atA = bandsNear( pair.greyA, s.inA, alongA, pair.object, pair.tolerancePx, alongHalfPx );
      if ( atA.empty() )
        return false;
      const std::vector<CrossSection> atB = bandsNear( pair.greyB, s.inB, alongB, pair.object, pair.tolerancePx, alongHalfPx );
      if ( atB.empty() )
        return false;
      s.status = RevisionStatus::Confirmed;
      s.widthPx = atA.front().widthPx;
      s.offsetPx = atA.front().offsetPx;
      s.foundA = s.inA + atA.front().offsetPx * normalOf( alongA );
      s.foundB = s.inB + atB.front().offsetPx * normalOf( alongB );
      return true;
    }

    //! The bands off the course within the shift allowed in A whose ground point shows a band in B.
    std::vector<Sample::Candidate> candidatesOffCourse( const Sample &s, const Eigen::Vector2d &alongA, const Eigen::Vector2d &alongB, const PairView &pair, double alongHalfPx )
    {
      std::vector<Sample::Candidate> candidates;
      for ( const CrossSection &band : bandsNear( pair.greyA, s.inA, alongA, pair.object, pair.shiftMaxPx, alongHalfPx ) )
      {
        if ( std::abs( band.offsetPx ) - 0.5 * band.widthPx <= pair.tolerancePx )
          continue; // touching the course: the road itself, its kerb or shoulder (seen in A only), not a road moved
        const Eigen::Vector2d inA = s.inA + band.offsetPx * normalOf( alongA );
        const std::optional<Eigen::Vector3d> ground = pair.mapping.groundPoint( pair.mapping.imageA(), inA );
        if ( !ground )
          continue;
        Eigen::Vector2d inB;
        if ( !inFrame( pair.mapping.imageB(), *ground, inB, 2.0 ) )
          continue;
        const std::vector<CrossSection> there = bandsNear( pair.greyB, inB, alongB, pair.object, pair.tolerancePx, alongHalfPx );
        if ( !there.empty() )
          candidates.push_back( { band.offsetPx, band.widthPx, inA, inB + there.front().offsetPx * normalOf( alongB ), ( *ground - s.ground ).head<2>().norm() } );
      }
      return candidates;
    }
  } // namespace

  /**
   * One sample's status: a band on the mapped course in both images
   * (confirmed); else the nearest band within the shift allowed in A whose
   * ground point shows a band in B (moved); else not found. The course is
   * looked at on profiles averaged over 1.5 px along it and, where they show
   * no band, over PairView::longAlongPx (markings, cars and a tree's shadow
   * on a road hide its band from the short profiles; a long one crossing
   * another road or a field's edge obliquely can make a band of them, so it
   * confirms only where the short ones find nothing). The bands off the
   * course are taken from both, nearest first.
   */
  void check( Sample &s, const Eigen::Vector2d &alongA, const Eigen::Vector2d &alongB, const PairView &pair )
  {
    constexpr double kShortPx = 1.5;
    const bool longer = pair.longAlongPx > kShortPx;
    if ( confirmOnCourse( s, alongA, alongB, pair, kShortPx ) || ( longer && confirmOnCourse( s, alongA, alongB, pair, pair.longAlongPx ) ) )
      return;
    s.status = RevisionStatus::NotFound;
    // off the course both: which band a moved stretch runs along is settled on the offsets its samples share
    s.candidates = candidatesOffCourse( s, alongA, alongB, pair, kShortPx );
    if ( longer )
      for ( const Sample::Candidate &c : candidatesOffCourse( s, alongA, alongB, pair, pair.longAlongPx ) )
        if ( std::none_of( s.candidates.begin(), s.candidates.end(), [&]( const Sample::Candidate &d ) { return std::abs( d.offsetPx - c.offsetPx ) <= 1.5; } ) )
          s.candidates.push_back( c );
    std::sort( s.candidates.begin(), s.candidates.end(), []( const Sample::Candidate &x, const Sample::Candidate &y ) { return std::abs( x.offsetPx ) < std::abs( y.offsetPx ); } );
    if ( s.candidates.empty() )
      return;
    // the nearest for now; a moved stretch settles on the offset its samples share (settleShifts)
    s.status = RevisionStatus::Moved;
    s.foundA = s.candidates.front().inA;
    s.foundB = s.candidates.front().inB;
    s.shiftM = s.candidates.front().shiftM;
    s.offsetPx = s.candidates.front().offsetPx;
    s.widthPx = s.candidates.front().widthPx;
  }

  namespace
  {
    /**
     * On a bend the moved road's offset from the mapped course drifts from
     * sample to sample, and a band beside it (a verge, a strip of field)
     * can gather the most support at one sample: a sample whose band lies
     * more than kOffCoursePx from the median of its moved neighbours' (3
     * either side, at least 4 of them) takes its band nearest that median
     * where one lies within kOnCoursePx.
     */
    void keepToNeighboursCourse( const std::vector<Sample> &samples, std::vector<const Sample::Candidate *> &chosen )
    {
      constexpr size_t kReach = 3;
      constexpr double kOffCoursePx = 3.0, kOnCoursePx = 2.0;
      const std::vector<const Sample::Candidate *> settled = chosen;
      for ( size_t k = 0; k < samples.size(); ++k )
      {
        if ( !settled[k] )
          continue;
        std::vector<double> around;
        for ( size_t j = k > kReach ? k - kReach : 0; j < std::min( samples.size(), k + kReach + 1 ); ++j )
          if ( j != k && settled[j] )
            around.push_back( settled[j]->offsetPx );
        if ( around.size() < 4 )
          continue;
        std::nth_element( around.begin(), around.begin() + around.size() / 2, around.end() );
        const double median = around[around.size() / 2];
        if ( std::abs( settled[k]->offsetPx - median ) <= kOffCoursePx )
          continue;
        for ( const Sample::Candidate &c : samples[k].candidates )
          if ( std::abs( c.offsetPx - median ) <= kOnCoursePx && ( chosen[k] == settled[k] || std::abs( c.offsetPx - median ) < std::abs( chosen[k]->offsetPx - median ) ) )
            chosen[k] = &c;
      }
    }
  } // namespace

  /**
   * A road moved as a whole: of a moved sample's bands (those in A that B
   * confirms), the one whose offset from the course the bands of the
   * neighbouring samples (5 either side) share most, within 1.5 px, and
   * at least 3 of them; a sample without such a band is not moved. The
   * moved road is found at about the same offset sample after sample; a
   * band of grass at any offset. Its shoulders are too, on either side:
   * a band so chosen that borders a wider one with its twin beyond is the
   * shoulder, and the road between them is taken. Then each sample is
   * held to its neighbours' course (keepToNeighboursCourse()).
   */
  void settleShifts( std::vector<Sample> &samples )
  {
    std::vector<const Sample::Candidate *> chosen( samples.size(), nullptr );
    for ( size_t k = 0; k < samples.size(); ++k )
    {
      if ( samples[k].status != RevisionStatus::Moved )
        continue;
      // support from 5 samples either side; ties go to the support from 15 either side (a band along the
      // road for a few samples, a strip of field beside it, loses there), then to the wider band (the road, not its kerb)
      const auto supportOf = [&]( const Sample::Candidate &c, size_t reach ) {
        int support = 0;
        for ( size_t j = k > reach ? k - reach : 0; j < std::min( samples.size(), k + reach + 1 ); ++j )
          if ( j != k && samples[j].status == RevisionStatus::Moved )
            for ( const Sample::Candidate &d : samples[j].candidates )
              if ( std::abs( d.offsetPx - c.offsetPx ) <= 1.5 )
              {
                ++support;
                break;
              }
        return support;
      };
      int bestSupport = 0, bestWide = 0;
      for ( const Sample::Candidate &c : samples[k].candidates )
      {
        const int support = supportOf( c, 5 ), wide = supportOf( c, 15 );
        if ( support > bestSupport || ( support == bestSupport && ( wide > bestWide || ( wide == bestWide && chosen[k] && c.widthPx > chosen[k]->widthPx ) ) ) )
        {
          bestSupport = support;
          bestWide = wide;
          chosen[k] = &c;
        }
      }
      if ( bestSupport < 3 )
      {
        chosen[k] = nullptr;
        continue;
      }
      // the road, not its shoulder: a wider band that the settled one touches on one side and a band like it on the
      // other is a road between its shoulders (the three run along the road at the same offsets, and a car or a shadow
      // hides the road's band from a sample or two); a wide strip of field beside a road has no such twin
      const Sample::Candidate *verge = chosen[k];
      int roadSupport = std::max( 3, bestSupport - kSupportLostToCars ) - 1;
      for ( const Sample::Candidate &c : samples[k].candidates )
        if ( c.widthPx > kRoadOverVerge * verge->widthPx && touching( c, *verge ) && hasTwinBeyond( samples[k].candidates, c, *verge ) )
          if ( const int support = supportOf( c, 5 ); support > roadSupport )
          {
            roadSupport = support;
            chosen[k] = &c;
          }
    }
    keepToNeighboursCourse( samples, chosen );
    for ( size_t k = 0; k < samples.size(); ++k )
    {
      Sample &s = samples[k];
      if ( s.status != RevisionStatus::Moved )
        continue;
      if ( !chosen[k] )
      {
        s.status = RevisionStatus::NotFound;
        continue;
      }
      s.foundA = chosen[k]->inA;
      s.foundB = chosen[k]->inB;
      s.shiftM = chosen[k]->shiftM;
      s.offsetPx = chosen[k]->offsetPx;
      s.widthPx = chosen[k]->widthPx;
    }
  }

  /**
   * A road runs on: a confirmed or moved sample counts only where a
   * sample of its status within 2 either side found its band in the first
   * image within 2 px of the same offset from the course and within 40 %
   * of the same width. Bands a
   * little brighter or darker than their sides, which grass with a coarse
   * grain holds everywhere, come at any offset and width from sample to
   * sample.
   */
  void requireContinuity( std::vector<Sample> &samples )
  {
    const auto continues = [&]( size_t k, size_t j ) {
      const Sample &s = samples[k], &t = samples[j];
      return t.status == s.status && std::abs( s.offsetPx - t.offsetPx ) <= 2.0 && std::abs( s.widthPx - t.widthPx ) <= 0.4 * std::max( s.widthPx, t.widthPx );
    };
    std::vector<size_t> isolated;
    for ( size_t k = 0; k < samples.size(); ++k )
      if ( samples[k].status == RevisionStatus::Confirmed || samples[k].status == RevisionStatus::Moved )
      {
        bool continued = false;
        for ( size_t j = k > 2 ? k - 2 : 0; j < std::min( samples.size(), k + 3 ) && !continued; ++j )
          continued = j != k && continues( k, j );
        if ( !continued )
          isolated.push_back( k );
      }
    for ( const size_t k : isolated )
      samples[k].status = RevisionStatus::NotFound;
  }

  namespace
  {
    /**
     * Whether the band `widthPx` wide at `offsetPx` across `along` at `at`
     * is one a junction opens: uniform inside (robust spread), one side at
     * least the minimum contrast from it, either sign; the other is the
     * surface of the road that joins, of any grey.
     */
    bool openBandAt( const GreyTiles &grey, const Eigen::Vector2d &at, const Eigen::Vector2d &along, double offsetPx, double widthPx, const LineObjectOptions &object )
    {
      constexpr int kFlankPx = 3, kBlurPx = 1;
      const int half = static_cast<int>( std::ceil( std::abs( offsetPx ) + 0.5 * widthPx ) ) + kBlurPx + kFlankPx + 1;
      const GreyWindow window = grey.around( at, half + 4 );
      const std::vector<double> profile = sampleCrossProfile( window.pixels, window.toWindow( at ), along, half, 1 );
      const double centre = half + offsetPx;
      std::vector<double> inside, left, right;
      for ( int t = 0; t < static_cast<int>( profile.size() ); ++t )
      {
        const double d = t - centre;
        if ( !std::isfinite( profile[t] ) )
          continue;
        if ( std::abs( d ) <= 0.5 * widthPx - kBlurPx )
          inside.push_back( profile[t] );
        else if ( d < 0.0 && std::abs( d ) >= 0.5 * widthPx + kBlurPx && std::abs( d ) < 0.5 * widthPx + kBlurPx + kFlankPx )
          left.push_back( profile[t] );
        else if ( d > 0.0 && d >= 0.5 * widthPx + kBlurPx && d < 0.5 * widthPx + kBlurPx + kFlankPx )
          right.push_back( profile[t] );
      }
      if ( inside.size() < 2 || left.empty() || right.empty() )
        return false;
      const auto median = []( std::vector<double> v ) {
        std::nth_element( v.begin(), v.begin() + v.size() / 2, v.end() );
        return v[v.size() / 2];
      };
      const double level = median( inside );
      std::vector<double> deviations;
      for ( const double g : inside )
        deviations.push_back( std::abs( g - level ) );
      if ( 1.4826 * median( deviations ) > object.maxVariation )
        return false;
      // one side stands out; the other is the surface of the road that joins
      const double toLeft = std::abs( level - median( left ) ), toRight = std::abs( level - median( right ) );
      return std::max( toLeft, toRight ) >= object.minContrast;
    }
  } // namespace

  void confirmThroughJunctions( std::vector<Sample> &samples, const PairView &pair )
  {
    constexpr double kOffsetPx = 2.0, kWidthShare = 0.4;
    const auto inGap = [&]( size_t k ) { return samples[k].status == RevisionStatus::NotFound || samples[k].status == RevisionStatus::Moved; };
    const auto confirmed = [&]( size_t k ) { return samples[k].status == RevisionStatus::Confirmed; };
    // a confirmed sample's band offset across the course in B
    const auto offsetInB = [&]( size_t k ) { return ( samples[k].foundB - samples[k].inB ).dot( normalOf( directionAt( samples, k, false ) ) ); };
    for ( size_t first = 0; first < samples.size(); )
    {
      if ( !inGap( first ) )
      {
        ++first;
        continue;
      }
      size_t end = first;
      while ( end < samples.size() && inGap( end ) )
        ++end;
      // the confirmed samples either side; at the road's first or last sample the one there is
      std::vector<size_t> ends;
      if ( first > 0 && confirmed( first - 1 ) )
        ends.push_back( first - 1 );
      if ( end < samples.size() && confirmed( end ) )
        ends.push_back( end );
      const bool bounded = ( first > 0 ? confirmed( first - 1 ) : true ) && ( end < samples.size() ? confirmed( end ) : true );
      const Eigen::Vector2d from = samples[first > 0 ? first - 1 : first].inA, to = samples[end < samples.size() ? end : end - 1].inA;
      double reference = 0.0; // the road's width either side of the gap
      for ( const size_t k : ends )
        reference = std::max( reference, samples[k].widthPx );
      if ( ends.empty() || !bounded || ( to - from ).norm() > 2.0 * reference + 2.0 * pair.tolerancePx ||
           ( ends.size() == 2 && ( std::abs( samples[ends[0]].offsetPx - samples[ends[1]].offsetPx ) > kOffsetPx ||
                                   std::abs( samples[ends[0]].widthPx - samples[ends[1]].widthPx ) > kWidthShare * std::max( samples[ends[0]].widthPx, samples[ends[1]].widthPx ) ) ) )
      {
        first = end;
        continue;
      }
      double offsetA = 0.0, offsetB = 0.0, width = 0.0;
      for ( const size_t k : ends )
      {
        offsetA += samples[k].offsetPx / ends.size();
        offsetB += offsetInB( k ) / ends.size();
        width += samples[k].widthPx / ends.size();
      }
      for ( size_t k = first; k < end; ++k )
      {
        Sample &s = samples[k];
        const Eigen::Vector2d alongA = directionAt( samples, k, true ), alongB = directionAt( samples, k, false );
        if ( !openBandAt( pair.greyA, s.inA, alongA, offsetA, width, pair.object ) || !openBandAt( pair.greyB, s.inB, alongB, offsetB, width, pair.object ) )
          continue;
        s.status = RevisionStatus::Confirmed;
        s.candidates.clear();
        s.shiftM = 0.0;
        s.offsetPx = offsetA;
        s.widthPx = width;
        s.foundA = s.inA + offsetA * normalOf( alongA );
        s.foundB = s.inB + offsetB * normalOf( alongB );
      }
      first = end;
    }
  }

  //! Each sample's status replaced by the majority within `half` samples either side (ties keep their own).
  std::vector<RevisionStatus> majorityStatus( const std::vector<Sample> &samples, int half )
  {
    std::vector<RevisionStatus> out( samples.size() );
    for ( size_t i = 0; i < samples.size(); ++i )
    {
      std::map<RevisionStatus, int> votes;
      for ( size_t k = i > static_cast<size_t>( half ) ? i - half : 0; k < std::min( samples.size(), i + half + 1 ); ++k )
        ++votes[samples[k].status];
      RevisionStatus best = samples[i].status;
      for ( const auto &[status, count] : votes )
        if ( count > votes[best] )
          best = status;
      out[i] = best;
    }
    return out;
  }

} // namespace geostation::revision
