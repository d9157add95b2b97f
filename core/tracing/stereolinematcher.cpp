/***************************************************************************
  stereolinematcher.cpp - a traced line found in the stereo partner, in 3-D
 ***************************************************************************/
#include "tracing/stereolinematcher.h"
#include "geometry/rotation.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Geometry>

#include "adjustment/intersection.h"
#include "geometry/epipolar.h"
#include "tracing/linerelocation.h"

namespace geostation
{
  namespace
  {
    //! A window's sample offsets (pixels) along (direction, its normal), `along` x `across` samples one pixel apart.
    std::vector<Eigen::Vector2d> orientedOffsets( const Eigen::Vector2d &direction, int along, int across )
    {
      std::vector<Eigen::Vector2d> offsets;
      const Eigen::Vector2d normal = rightNormal( direction );
      for ( int a = -along / 2; a <= along / 2; ++a )
        for ( int b = -across / 2; b <= across / 2; ++b )
          offsets.push_back( a * direction + b * normal );
      return offsets;
    }

    /**
     * The reference window's samples on the road surface, to be seen from the partner: each sample's ray
     * meets the surface, and the surface may lie higher or lower than predicted there (the road plane from
     * the cameras' heights, a DEM), so the window is mapped for the height each candidate along the
     * epipolar curve stands for - the surface moved up or down by that much.
     */
    class SurfaceWindow
    {
      public:
        SurfaceWindow( const StereoImage &reference, const Eigen::Vector2d &centre, const std::vector<Eigen::Vector2d> &offsets, const StereoImage &partner,
                       const GroundOfPixel &groundOfPixel )
          : mPartner( partner )
        {
          for ( size_t k = 0; k <= offsets.size(); ++k )
          {
            // the centre last
            const Eigen::Vector2d pixel = k < offsets.size() ? Eigen::Vector2d( centre + offsets[k] ) : centre;
            const std::optional<Ray> ray = reference.image->worldRayFromPixel( pixel );
            const std::optional<Eigen::Vector3d> ground = groundOfPixel( *reference.image, pixel );
            if ( !ray || !ground || ray->direction.z() > -1e-3 )
            {
              mGround.clear();
              return;
            }
            mGround.push_back( *ground );
            mRay.push_back( ray->direction );
          }
        }

        bool ok() const { return !mGround.empty(); }

        //! The samples' offsets in the partner from the centre's, the surface `raisedM` above the prediction (2 cm steps); empty where one does not project.
        const std::vector<Eigen::Vector2d> &partnerOffsets( double raisedM )
        {
          const int level = static_cast<int>( std::lround( raisedM / 0.02 ) );
          auto it = mLevels.find( level );
          if ( it != mLevels.end() )
            return it->second;
          std::vector<Eigen::Vector2d> &offsets = mLevels[level];
          const auto seen = [&]( size_t k ) -> std::optional<Eigen::Vector2d>
          {
            // along the sample's ray to the raised surface
            const GroundProjection p = mPartner.image->projectGroundToPixel( mGround[k] + ( 0.02 * level / mRay[k].z() ) * mRay[k] );
            return p.ok() ? std::optional<Eigen::Vector2d>( p.pixelInImage ) : std::nullopt;
          };
          const std::optional<Eigen::Vector2d> centre = seen( mGround.size() - 1 );
          for ( size_t k = 0; centre && k + 1 < mGround.size(); ++k )
          {
            const std::optional<Eigen::Vector2d> sample = seen( k );
            if ( !sample )
            {
              offsets.clear();
              break;
            }
            offsets.push_back( *sample - *centre );
          }
          return offsets;
        }

      private:
        const StereoImage &mPartner;
        std::vector<Eigen::Vector3d> mGround, mRay; // per sample, the centre last
        std::map<int, std::vector<Eigen::Vector2d>> mLevels;
    };

    //! Grey values at centre + each offset; false where one falls outside the image.
    bool sampleWindow( const cv::Mat &grey, const Eigen::Vector2d &centre, const std::vector<Eigen::Vector2d> &offsets, std::vector<double> &values )
    {
      values.clear();
      for ( const Eigen::Vector2d &offset : offsets )
      {
        const std::optional<double> g = sampleGrey( grey, centre + offset );
        if ( !g )
          return false;
        values.push_back( *g );
      }
      return true;
    }

    double ncc( const std::vector<double> &a, const std::vector<double> &b )
    {
      const size_t n = a.size();
      double ma = 0, mb = 0;
      for ( size_t i = 0; i < n; ++i )
      {
        ma += a[i];
        mb += b[i];
      }
      ma /= n;
      mb /= n;
      double sab = 0, saa = 0, sbb = 0;
      for ( size_t i = 0; i < n; ++i )
      {
        sab += ( a[i] - ma ) * ( b[i] - mb );
        saa += ( a[i] - ma ) * ( a[i] - ma );
        sbb += ( b[i] - mb ) * ( b[i] - mb );
      }
      return saa > 0 && sbb > 0 ? sab / std::sqrt( saa * sbb ) : 0.0;
    }

    //! The curve's vertices as one polyline (pieces joined in order).
    std::vector<Eigen::Vector2d> curvePolyline( const EpipolarCurve &curve )
    {
      std::vector<Eigen::Vector2d> out;
      for ( const auto &piece : curve.pieces )
        for ( const EpipolarVertex &v : piece )
          out.push_back( v.pixelInImage );
      return out;
    }

    //! Segment a-b crossing c-d: the parameter along a-b and c-d.
    bool crossing( const Eigen::Vector2d &a, const Eigen::Vector2d &b, const Eigen::Vector2d &c, const Eigen::Vector2d &d, double &t, double &u )
    {
      const Eigen::Vector2d r = b - a, s = d - c;
      const double den = r.x() * s.y() - r.y() * s.x();
      if ( std::abs( den ) < 1e-12 )
        return false;
      const Eigen::Vector2d q = c - a;
      t = ( q.x() * s.y() - q.y() * s.x() ) / den;
      u = ( q.x() * r.y() - q.y() * r.x() ) / den;
      return t >= 0 && t <= 1 && u >= 0 && u <= 1;
    }
  }

  //! Covariance of a ground point from the rig's pose sigmas (rigid shift and small rotations about the rig).
  Eigen::Matrix3d rigPoseCovariance( const ExteriorOrientation &exterior, const Eigen::Vector3d &point, const Eigen::Vector3d &rigCentre )
  {
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    if ( !exterior.sigma )
      return c;
    const ExteriorSigma &s = *exterior.sigma;
    c.diagonal() << s.x * s.x, s.y * s.y, s.z * s.z;
    const Eigen::Vector3d r = point - rigCentre;
    const double angles[3] = { s.omegaDeg, s.phiDeg, s.kappaDeg };
    for ( int i = 0; i < 3; ++i )
    {
      const Eigen::Vector3d j = Eigen::Vector3d( Eigen::Vector3d::Unit( i ) ).cross( r ) * ( angles[i] * kPi / 180.0 );
      c += j * j.transpose();
    }
    return c;
  }

  StartMatch matchStartInPartner( const StereoImage &reference, const Eigen::Vector2d &pixelInReference, const Eigen::Vector2d &directionInReference,
                                  const StereoImage &partner, const GroundOfPixel &groundOfPixel, const LineProfile &profile,
                                  const StartMatchOptions &options )
  {
    StartMatch out;
    const int across = std::max( options.windowAcrossPx, profile.kind == LineKind::Edge ? 0 : static_cast<int>( 2.5 * profile.widthPx + 4 ) ) | 1;
    const int along = std::max( options.windowAlongPx, 3 * across ) | 1;
    const auto fail = [&]( StartMatch::Status status, const std::string &why )
    {
      out.status = status;
      out.message = why;
      return out;
    };
    const std::optional<Eigen::Vector3d> ground = groundOfPixel( *reference.image, pixelInReference );
    const std::optional<Eigen::Vector3d> further = groundOfPixel( *reference.image, pixelInReference + 20.0 * directionInReference );
    if ( !ground || !further )
      return fail( StartMatch::Status::NoGround, "the start's ray does not reach the road surface" );
    const GroundProjection predicted = partner.image->projectGroundToPixel( *ground ), ahead = partner.image->projectGroundToPixel( *further );
    if ( !predicted.ok() || !predicted.inFrame || !ahead.ok() )
      return fail( StartMatch::Status::NotInView, "the start is not in view of " + partner.imageId );
    const Eigen::Vector2d directionInPartner = ( ahead.pixelInImage - predicted.pixelInImage ).normalized();
    const double distance = ( *ground - reference.image->exterior().projectionCentre ).norm();
    EpipolarOptions epipolar;
    epipolar.minDistanceM = 0.5 * distance;
    epipolar.maxDistanceM = 2.0 * distance;
    epipolar.maxSegmentPx = 0.5;
    const EpipolarCurve epipolarPieces = epipolarCurve( *reference.image, pixelInReference, *partner.image, epipolar );
    const std::vector<Eigen::Vector2d> curve = curvePolyline( epipolarPieces );
    std::vector<double> curveDistance;
    for ( const auto &piece : epipolarPieces.pieces )
      for ( const EpipolarVertex &v : piece )
        curveDistance.push_back( v.distanceM );
    if ( curve.size() < 2 )
      return fail( StartMatch::Status::NoEpipolarCurve, "the start's epipolar curve does not reach " + partner.imageId );
    // the distances along the ray at which the road surface may lie, +- the height tolerance
    const double depression = std::max( 0.02, ( reference.image->exterior().projectionCentre.z() - ground->z() ) / distance );
    const double nearest = distance - options.heightToleranceM / depression, farthest = distance + options.heightToleranceM / depression;
    // the template's samples in the partner through the road surface (a window of 60 px along a line 15 m
    // ahead covers 8 m of road, which a partner nearer to it sees scaled and sheared along its length; thesis
    // ch. 5), else along the line's direction there
    const std::vector<Eigen::Vector2d> templateOffsets = orientedOffsets( directionInReference, along, across );
    const std::vector<Eigen::Vector2d> orientedInPartner = orientedOffsets( directionInPartner, along, across );
    SurfaceWindow surface( reference, pixelInReference, templateOffsets, partner, groundOfPixel );
    const Eigen::Vector3d rayDirection = ( *ground - reference.image->exterior().projectionCentre ).normalized();
    std::vector<double> templateValues, values;
    if ( !sampleWindow( *reference.grey, pixelInReference, templateOffsets, templateValues ) )
      return fail( StartMatch::Status::AtBorder, "the start is too close to the border of " + reference.imageId );
    // the curve's vertex nearest the prediction, then every vertex within the search length either side
    size_t foot = 0;
    for ( size_t i = 1; i < curve.size(); ++i )
      if ( ( curve[i] - predicted.pixelInImage ).squaredNorm() < ( curve[foot] - predicted.pixelInImage ).squaredNorm() )
        foot = i;
    struct Candidate
    {
      double score;
      Eigen::Vector2d pixel;
      double raisedM; //!< the surface through it above the prediction
    };
    std::vector<Candidate> scored;
    for ( size_t i = 0; i < curve.size(); ++i )
    {
      if ( ( curve[i] - curve[foot] ).norm() > options.searchAlongCurvePx && ( curveDistance[i] < nearest || curveDistance[i] > farthest ) )
        continue;
      const std::vector<Eigen::Vector2d> *offsets = &orientedInPartner;
      // the surface through this candidate: as far above the prediction as its point on the start's ray
      const double raised = std::clamp( ( reference.image->exterior().projectionCentre + curveDistance[i] * rayDirection ).z() - ground->z(),
                                        -options.heightToleranceM, options.heightToleranceM );
      if ( surface.ok() )
      {
        const std::vector<Eigen::Vector2d> &shaped = surface.partnerOffsets( raised );
        if ( !shaped.empty() )
          offsets = &shaped;
      }
      if ( sampleWindow( *partner.grey, curve[i], *offsets, values ) )
        scored.push_back( { ncc( templateValues, values ), curve[i], raised } );
    }
    size_t best = 0;
    for ( size_t i = 1; i < scored.size(); ++i )
      if ( scored[i].score > scored[best].score )
        best = i;
    if ( scored.empty() || scored[best].score < options.minScore )
      return fail( StartMatch::Status::NotFound, "the line was not found in " + partner.imageId + " along the start's epipolar curve (best correlation " +
                   std::to_string( scored.empty() ? 0.0 : scored[best].score ).substr( 0, 4 ) + ")" );
    // a best score at either end of the candidates is no peak: the correlation still rises where the search
    // ends or the window leaves the partner image, and the line lies beyond (the caller tries a point further on)
    if ( ( best == 0 || best + 1 == scored.size() ) )
      return fail( StartMatch::Status::AtSearchEnd, "the line's correlation in " + partner.imageId + " peaks at the end of the start's search (best correlation " +
                   std::to_string( scored[best].score ).substr( 0, 4 ) + "): the start is not in full view there" );
    Eigen::Vector2d pixel = scored[best].pixel;
    {
      // parabola through the neighbours along the curve
      const double a = scored[best - 1].score, b = scored[best].score, c = scored[best + 1].score;
      const double den = a - 2 * b + c;
      if ( den < 0 )
      {
        const double shift = std::clamp( 0.5 * ( a - c ) / den, -0.5, 0.5 );
        pixel = shift > 0 ? Eigen::Vector2d( pixel + shift * ( scored[best + 1].pixel - pixel ) ) : Eigen::Vector2d( pixel - shift * ( scored[best - 1].pixel - pixel ) );
      }
    }
    out.status = StartMatch::Status::Ok;
    out.pixelInImage = pixel;
    out.direction = directionInPartner;
    {
      // the line's direction on the surface through the match
      const Eigen::Vector3d centre = reference.image->exterior().projectionCentre;
      const auto raise = [&]( const Eigen::Vector3d &p )
      {
        const Eigen::Vector3d ray = ( p - centre ).normalized();
        return Eigen::Vector3d( p + ( scored[best].raisedM / std::min( ray.z(), -1e-3 ) ) * ray );
      };
      const GroundProjection at = partner.image->projectGroundToPixel( raise( *ground ) ), beyond = partner.image->projectGroundToPixel( raise( *further ) );
      if ( at.ok() && beyond.ok() && ( beyond.pixelInImage - at.pixelInImage ).norm() > 1e-6 )
        out.direction = ( beyond.pixelInImage - at.pixelInImage ).normalized();
    }
    out.score = scored[best].score;
    return out;
  }

  double pixelsPerMetreAcross( const OrientedImage &image, const Eigen::Vector3d &ground, const Eigen::Vector3d &alongGround )
  {
    const Eigen::Vector3d along = Eigen::Vector3d( alongGround.x(), alongGround.y(), 0.0 ).normalized();
    const Eigen::Vector3d across( -along.y(), along.x(), 0.0 );
    if ( !along.allFinite() )
      return 0.0;
    const double h = 0.05; // m
    const GroundProjection a0 = image.projectGroundToPixel( ground - h * along ), a1 = image.projectGroundToPixel( ground + h * along );
    const GroundProjection c0 = image.projectGroundToPixel( ground - h * across ), c1 = image.projectGroundToPixel( ground + h * across );
    if ( !a0.ok() || !a1.ok() || !c0.ok() || !c1.ok() )
      return 0.0;
    const Eigen::Vector2d lineInImage = a1.pixelInImage - a0.pixelInImage;
    if ( lineInImage.norm() < 1e-9 )
      return 0.0;
    return std::abs( rightNormal( lineInImage.normalized() ).dot( c1.pixelInImage - c0.pixelInImage ) ) / ( 2 * h );
  }

  std::vector<LineVertex3d> intersectLineVertices( const StereoImage &reference, const std::vector<Eigen::Vector2d> &referencePoints, const std::vector<double> &referenceSigmaPx,
      const StereoImage &partner, const FollowResult &partnerFollowed, const GroundOfPixel &groundOfPixel, const VertexMatchOptions &options,
      const LineRelocation *partnerRelocation )
  {
    const std::vector<Eigen::Vector2d> &partnerLine = partnerFollowed.points;
    const std::vector<double> &partnerSigmaPx = partnerFollowed.sigmaPx;
    const auto bridged = [&]( size_t b ) { return b + 1 < partnerFollowed.bridged.size() && partnerFollowed.bridged[b + 1]; };
    std::vector<LineVertex3d> out;
    if ( partnerLine.size() < 2 )
      return out;
    const Eigen::Vector3d rigCentre = 0.5 * ( reference.image->exterior().projectionCentre + partner.image->exterior().projectionCentre );
    for ( size_t i = 0; i < referencePoints.size(); ++i )
    {
      const Eigen::Vector2d &p = referencePoints[i];
      const std::optional<Eigen::Vector3d> ground = groundOfPixel( *reference.image, p );
      if ( !ground )
        continue;
      const GroundProjection predicted = partner.image->projectGroundToPixel( *ground );
      const double distance = ( *ground - reference.image->exterior().projectionCentre ).norm();
      EpipolarOptions epipolar;
      const double depression = std::max( 0.02, ( reference.image->exterior().projectionCentre.z() - ground->z() ) / distance );
      epipolar.minDistanceM = std::max( 0.1, distance - options.heightToleranceM / depression );
      epipolar.maxDistanceM = distance + options.heightToleranceM / depression;
      epipolar.maxSegmentPx = 2.0;
      const std::vector<Eigen::Vector2d> curve = curvePolyline( epipolarCurve( *reference.image, p, *partner.image, epipolar ) );
      // the crossing of the curve and the partner's line nearest the prediction
      bool found = false;
      Eigen::Vector2d conjugate = Eigen::Vector2d::Zero();
      double sigma = 0.0, bestDistance = 0.0, sigmaLine = 0.0;
      Eigen::Vector2d partnerDirection( 0, -1 ), curveDirection( 1, 0 );
      for ( size_t a = 0; a + 1 < curve.size(); ++a )
        for ( size_t b = 0; b + 1 < partnerLine.size(); ++b )
        {
          double t, u;
          if ( bridged( b ) || !crossing( curve[a], curve[a + 1], partnerLine[b], partnerLine[b + 1], t, u ) )
            continue;
          const Eigen::Vector2d c = curve[a] + t * ( curve[a + 1] - curve[a] );
          const Eigen::Vector2d dc = ( curve[a + 1] - curve[a] ).normalized(), dl = ( partnerLine[b + 1] - partnerLine[b] ).normalized();
          const double sine = std::abs( dc.x() * dl.y() - dc.y() * dl.x() );
          if ( sine < options.minCrossingSine )
            continue;
          const double d = predicted.ok() ? ( c - predicted.pixelInImage ).norm() : 0.0;
          if ( found && d >= bestDistance )
            continue;
          found = true;
          bestDistance = d;
          conjugate = c;
          const double lineSigma = ( 1 - u ) * partnerSigmaPx[b] + u * partnerSigmaPx[b + 1];
          sigma = std::min( options.maxPartnerSigmaPx, std::max( options.pixelSigmaFloorPx, lineSigma ) / sine );
          sigmaLine = sigma * sine;
          partnerDirection = dl;
          curveDirection = dc;
        }
      if ( !found )
        continue;
      if ( partnerRelocation && referencePoints.size() > 1 )
      {
        // the partner's line located again across the conjugate, over the same length of line on the ground
        const size_t n = i + 1 < referencePoints.size() ? i + 1 : i - 1;
        const std::optional<Eigen::Vector3d> neighbour = groundOfPixel( *reference.image, referencePoints[n] );
        const GroundProjection a = partner.image->projectGroundToPixel( *ground );
        const GroundProjection b = neighbour ? partner.image->projectGroundToPixel( *neighbour ) : GroundProjection();
        const double metres = neighbour ? ( *neighbour - *ground ).norm() : 0.0;
        if ( a.ok() && b.ok() && metres > 1e-3 )
        {
          const double pxPerM = ( b.pixelInImage - a.pixelInImage ).norm() / metres;
          const double range = ( *ground - partner.image->exterior().projectionCentre ).head<2>().norm();
          const Eigen::Vector2d normal = rightNormal( partnerDirection );
          const double crossing = normal.dot( curveDirection );
          if ( const std::optional<LineHit> hit = relocateOnLine( partner, conjugate, partnerDirection, pxPerM, range, *partnerRelocation ) )
            if ( std::abs( crossing ) >= options.minCrossingSine )
            {
              conjugate += curveDirection * ( normal.dot( hit->pixelInImage - conjugate ) / crossing );
              const double sine = std::abs( crossing );
              sigma = std::min( options.maxPartnerSigmaPx, std::max( options.pixelSigmaFloorPx, hit->sigmaPx ) / sine );
              sigmaLine = sigma * sine;
            }
        }
      }
      double referenceFloorPx = options.pixelSigmaFloorPx;
      if ( options.lineSigmaM > 0 && referencePoints.size() > 1 )
      {
        // the line's own sigma on the road, in each image's pixels
        const size_t n = i + 1 < referencePoints.size() ? i + 1 : i - 1;
        if ( const std::optional<Eigen::Vector3d> neighbour = groundOfPixel( *reference.image, referencePoints[n] ) )
        {
          const Eigen::Vector3d along = *neighbour - *ground;
          referenceFloorPx = std::max( referenceFloorPx, options.lineSigmaM * pixelsPerMetreAcross( *reference.image, *ground, along ) );
          const double partnerFloorPx = options.lineSigmaM * pixelsPerMetreAcross( *partner.image, *ground, along );
          if ( sigmaLine < partnerFloorPx )
          {
            sigma *= partnerFloorPx / sigmaLine;
            sigmaLine = partnerFloorPx;
          }
        }
      }
      std::vector<RayObservation> rays { { reference.image, p, std::max( referenceFloorPx, referenceSigmaPx[i] ) }, { partner.image, conjugate, sigma } };
      const IntersectionSummary s = intersectRays( rays );
      if ( !s.ok() )
        continue;
      LineVertex3d v;
      v.point = s.point;
      v.covariance = s.covariance;
      if ( options.propagateExterior )
        v.covariance += rigPoseCovariance( reference.image->exterior(), s.point, rigCentre );
      v.sigmaM = v.covariance.diagonal().cwiseMax( 0.0 ).cwiseSqrt();
      v.pixelInReference = p;
      v.pixelInPartner = conjugate;
      v.residualReferencePx = s.residuals[0].residualPx;
      v.residualPartnerPx = s.residuals[1].residualPx;
      v.rangeM = s.residuals[0].rangeM;
      v.sigmaReferencePx = rays[0].sigmaPx;
      v.sigmaPartnerLinePx = sigmaLine;
      v.partnerLineDirection = partnerDirection;
      out.push_back( v );
    }
    return out;
  }

  void intervalPoints( const FollowResult &followed, double spacingPx, std::vector<Eigen::Vector2d> &points, std::vector<double> &sigmas )
  {
    const std::vector<Eigen::Vector2d> &line = followed.points;
    const std::vector<double> &sigmaPx = followed.sigmaPx;
    points.clear();
    sigmas.clear();
    if ( line.empty() )
      return;
    points.push_back( line.front() );
    sigmas.push_back( sigmaPx.front() );
    for ( size_t i = 0; i + 1 < line.size(); ++i )
    {
      const bool gap = i + 1 < followed.bridged.size() && followed.bridged[i + 1];
      const double length = ( line[i + 1] - line[i] ).norm();
      const int n = gap ? 1 : std::max( 1, static_cast<int>( std::ceil( length / spacingPx ) ) );
      for ( int k = 1; k <= n; ++k )
      {
        const double t = static_cast<double>( k ) / n;
        points.push_back( line[i] + t * ( line[i + 1] - line[i] ) );
        sigmas.push_back( t < 0.5 ? sigmaPx[i] : sigmaPx[i + 1] );
      }
    }
  }

} // namespace geostation
