/***************************************************************************
  multistationvertices.cpp - traced vertices seen from the stations before
 ***************************************************************************/
#include "tracing/multistationvertices.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace geostation
{
  namespace
  {
    //! One observation of a vertex: a point (col, row) or a position across a line (one row).
    struct Observation
    {
      const OrientedImage *image = nullptr;
      size_t station = 0;                  //!< 0: the vertex's own
      bool point = false;
      Eigen::Vector2d pixel = Eigen::Vector2d::Zero(); //!< the point, or a point on the line
      Eigen::Vector2d normal = Eigen::Vector2d::Zero(); //!< across the line
      double sigmaPx = 0.0;
      std::string imageId;
    };

    //! The stations' pose data: rig centre and the exterior orientation carrying the sigmas.
    struct Rig
    {
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      const ExteriorOrientation *pose = nullptr;
    };

    Rig rigOf( const StationView &view )
    {
      Rig rig;
      for ( const StereoImage &image : view.images )
        rig.centre += image.image->exterior().projectionCentre;
      rig.centre /= static_cast<double>( std::max<size_t>( 1, view.images.size() ) );
      rig.pose = &view.images.front().image->exterior();
      return rig;
    }

    //! Pixel of a ground point and its Jacobian (px / m) by central differences; false when it does not project.
    bool projectWithJacobian( const OrientedImage &image, const Eigen::Vector3d &point, Eigen::Vector2d &pixel, Eigen::Matrix<double, 2, 3> &jacobian )
    {
      const GroundProjection p = image.projectGroundToPixel( point );
      if ( !p.ok() )
        return false;
      pixel = p.pixelInImage;
      constexpr double h = 1e-3;
      for ( int i = 0; i < 3; ++i )
      {
        const Eigen::Vector3d d = h * Eigen::Vector3d::Unit( i );
        const GroundProjection a = image.projectGroundToPixel( point + d ), b = image.projectGroundToPixel( point - d );
        if ( !a.ok() || !b.ok() )
          return false;
        jacobian.col( i ) = ( a.pixelInImage - b.pixelInImage ) / ( 2 * h );
      }
      return true;
    }

    struct Solution
    {
      bool ok = false;
      Eigen::Vector3d point = Eigen::Vector3d::Zero();
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      std::vector<double> normalised; //!< per observation: largest |w| of its rows
      double omega = 0.0;             //!< v^T Sigma^-1 v at the solution
      int redundancy = 0;             //!< rows - 3
    };

    /**
     * Generalised least squares: the rows of one station are correlated
     * through its pose, Sigma_s = diag(sigma^2) + A_s P_s A_s^T.
     */
    Solution adjust( const std::vector<Observation> &observations, const std::vector<Rig> &rigs, Eigen::Vector3d point )
    {
      Solution out;
      int m = 0;
      for ( const Observation &o : observations )
        m += o.point ? 2 : 1;
      Eigen::VectorXd f( m );
      Eigen::MatrixXd a( m, 3 ), sigma( m, m );
      for ( int iteration = 0; iteration < 10; ++iteration )
      {
        sigma.setZero();
        std::vector<int> firstRow;
        int row = 0;
        for ( const Observation &o : observations )
        {
          Eigen::Vector2d pixel;
          Eigen::Matrix<double, 2, 3> j;
          if ( !projectWithJacobian( *o.image, point, pixel, j ) )
            return out;
          firstRow.push_back( row );
          if ( o.point )
          {
            f.segment<2>( row ) = pixel - o.pixel;
            a.block<2, 3>( row, 0 ) = j;
            sigma( row, row ) = sigma( row + 1, row + 1 ) = o.sigmaPx * o.sigmaPx;
            row += 2;
          }
          else
          {
            f( row ) = o.normal.dot( pixel - o.pixel );
            a.row( row ) = o.normal.transpose() * j;
            sigma( row, row ) = o.sigmaPx * o.sigmaPx;
            row += 1;
          }
        }
        // the pose: every row of a station moves with the same displacement of the point
        for ( size_t s = 0; s < rigs.size(); ++s )
        {
          if ( !rigs[s].pose || !rigs[s].pose->sigma )
            continue;
          const Eigen::Matrix3d p = rigPoseCovariance( *rigs[s].pose, point, rigs[s].centre );
          std::vector<int> rows;
          for ( size_t i = 0; i < observations.size(); ++i )
            if ( observations[i].station == s )
              for ( int r = 0; r < ( observations[i].point ? 2 : 1 ); ++r )
                rows.push_back( firstRow[i] + r );
          for ( const int r : rows )
            for ( const int c : rows )
              sigma( r, c ) += a.row( r ) * p * a.row( c ).transpose();
        }
        const Eigen::LLT<Eigen::MatrixXd> llt( sigma );
        if ( llt.info() != Eigen::Success )
          return out;
        const Eigen::MatrixXd wa = llt.solve( a );
        const Eigen::Matrix3d normal = a.transpose() * wa;
        const Eigen::FullPivLU<Eigen::Matrix3d> lu( normal );
        if ( !lu.isInvertible() )
          return out;
        const Eigen::Vector3d delta = -lu.solve( wa.transpose() * f );
        point += delta;
        out.covariance = lu.inverse();
        if ( delta.norm() < 1e-7 )
        {
          // normalised residuals: f / sqrt(diag(Sigma - A N^-1 A^T)), the rows' residuals at the solution
          const Eigen::MatrixXd qv = sigma - a * out.covariance * a.transpose();
          int r = 0;
          for ( const Observation &o : observations )
          {
            double w = 0.0;
            for ( int k = 0; k < ( o.point ? 2 : 1 ); ++k, ++r )
              if ( qv( r, r ) > 1e-12 )
                w = std::max( w, std::abs( f( r ) + a.row( r ).dot( delta ) ) / std::sqrt( qv( r, r ) ) );
            out.normalised.push_back( w );
          }
          const Eigen::VectorXd v = f + a * delta;
          out.omega = v.dot( llt.solve( v ) );
          out.redundancy = m - 3;
          out.ok = true;
          out.point = point;
          return out;
        }
      }
      return out;
    }

    //! The 3-D direction of the line at vertex i, from its neighbours.
    Eigen::Vector3d tangentAt( const std::vector<LineVertex3d> &vertices, size_t i, const Eigen::Vector3d &fallback )
    {
      const size_t a = i > 0 ? i - 1 : i, b = i + 1 < vertices.size() ? i + 1 : i;
      const Eigen::Vector3d d = vertices[b].point - vertices[a].point;
      return d.norm() > 0.05 ? Eigen::Vector3d( d.normalized() ) : fallback.normalized();
    }
  }

  std::vector<LineVertex3d> verticesByLocatingInPartner( const std::vector<Eigen::Vector2d> &referencePoints, const std::vector<double> &referenceSigmaPx,
      const StationView &own, const GroundOfPixel &groundOfPixel, const LineProfile &profile, double widthTimesRange, double heightToleranceM,
      const MultiStationOptions &options )
  {
    std::vector<LineVertex3d> out;
    if ( own.images.size() < 2 )
      return out;
    const OrientedImage &reference = *own.images[0].image, &partner = *own.images[1].image;
    const cv::Mat &grey = *own.images[1].grey;
    const std::vector<Rig> rigs { rigOf( own ) };
    const Eigen::Vector3d camera = reference.exterior().projectionCentre;
    for ( size_t i = 0; i < referencePoints.size(); ++i )
    {
      const Eigen::Vector2d &p = referencePoints[i];
      const std::optional<Eigen::Vector3d> ground = groundOfPixel( reference, p );
      const size_t n = i + 1 < referencePoints.size() ? i + 1 : ( i > 0 ? i - 1 : i );
      const std::optional<Eigen::Vector3d> neighbour = n != i ? groundOfPixel( reference, referencePoints[n] ) : std::nullopt;
      if ( !ground || !neighbour || ( *neighbour - *ground ).norm() < 0.05 )
        continue;
      Eigen::Vector2d pixel;
      Eigen::Matrix<double, 2, 3> j;
      if ( !projectWithJacobian( partner, *ground, pixel, j ) || pixel.x() < options.marginPx || pixel.y() < options.marginPx ||
           pixel.x() > grey.cols - options.marginPx || pixel.y() > grey.rows - options.marginPx )
        continue;
      const Eigen::Vector2d along = j * ( *neighbour - *ground ) * ( n > i ? 1.0 : -1.0 );
      const Eigen::Vector3d ray = ( *ground - camera ).normalized();
      const Eigen::Vector2d epipolar = j * ray;
      if ( along.norm() < 1e-6 || epipolar.norm() < 1e-9 )
        continue;
      const Eigen::Vector2d direction = along.normalized(), normal = rightNormal( direction );
      // the line must cross the epipolar curve, not run along it
      if ( std::abs( normal.dot( epipolar.normalized() ) ) < options.minCrossingSine )
        continue;
      LineProfile there = profile, here = profile;
      const double range = ( *ground - partner.exterior().projectionCentre ).head<2>().norm();
      if ( profile.kind != LineKind::Edge && widthTimesRange > 0 )
      {
        there.widthPx = widthTimesRange / std::max( range, 1.0 );
        here.widthPx = widthTimesRange / std::max( ( *ground - camera ).head<2>().norm(), 1.0 );
      }
      // the reference point must itself be on the line (a follower may have drifted off it where the partner's line stopped)
      const Eigen::Vector2d referenceDirection = ( referencePoints[n] - p ).normalized() * ( n > i ? 1.0 : -1.0 );
      if ( !locateLine( *own.images[0].grey, p, referenceDirection, here, locateOptionsFor( here, FollowOptions(), options.onLineTolerancePx ) ) )
        continue;
      // where the road surface may lie along the reference ray: +- the height tolerance
      const double depression = std::max( 0.02, -ray.z() );
      const double sigmaPredicted = std::abs( normal.dot( epipolar ) ) * heightToleranceM / depression;
      const double searchHalf = std::clamp( sigmaPredicted, options.minSearchHalfPx, options.maxSearchHalfPx );
      const std::optional<LineHit> hit = locateLine( grey, pixel, direction, there, locateOptionsFor( there, FollowOptions(), searchHalf ) );
      if ( !hit )
        continue;
      double sigmaHit = std::max( options.sigmaFloorPx, hit->sigmaPx ), sigmaReference = std::max( options.sigmaFloorPx, referenceSigmaPx[i] );
      if ( options.lineSigmaM > 0 )
      {
        // the line's own sigma on the road, in each image's pixels (as for the partner's followed line)
        const Eigen::Vector3d alongGround = *neighbour - *ground;
        sigmaHit = std::max( sigmaHit, options.lineSigmaM * pixelsPerMetreAcross( partner, *ground, alongGround ) );
        sigmaReference = std::max( sigmaReference, options.lineSigmaM * pixelsPerMetreAcross( reference, *ground, alongGround ) );
      }
      const std::vector<Observation> observations {
        { &reference, 0, true, p, Eigen::Vector2d::Zero(), sigmaReference, own.images[0].imageId },
        { &partner, 0, false, hit->pixelInImage, normal, sigmaHit, own.images[1].imageId } };
      const Solution solution = adjust( observations, rigs, *ground );
      if ( !solution.ok || std::abs( solution.point.z() - ground->z() ) > heightToleranceM )
        continue;
      LineVertex3d v;
      v.point = solution.point;
      v.covariance = solution.covariance;
      v.sigmaM = v.covariance.diagonal().cwiseMax( 0.0 ).cwiseSqrt();
      v.pixelInReference = p;
      v.pixelInPartner = hit->pixelInImage;
      v.residualReferencePx = reference.projectGroundToPixel( v.point ).pixelInImage - p;
      v.residualPartnerPx = normal * normal.dot( partner.projectGroundToPixel( v.point ).pixelInImage - hit->pixelInImage );
      v.rangeM = ( v.point - camera ).norm();
      v.sigmaReferencePx = observations[0].sigmaPx;
      v.sigmaPartnerLinePx = sigmaHit;
      v.partnerLineDirection = direction;
      out.push_back( v );
    }
    return out;
  }

  MultiStationSummary refineFromOtherStations( std::vector<LineVertex3d> &vertices, const StationView &own, const std::vector<StationView> &others,
      const LineProfile &profile, double widthTimesRange, const Eigen::Vector3d &lineDirection, const MultiStationOptions &options )
  {
    MultiStationSummary summary;
    if ( own.images.size() < 2 || others.empty() )
      return summary;
    std::vector<Rig> rigs { rigOf( own ) };
    for ( const StationView &view : others )
      rigs.push_back( view.images.empty() ? Rig() : rigOf( view ) );

    std::vector<bool> drop( vertices.size(), false ), confirmed( vertices.size(), false ), unconfirmed( vertices.size(), false );
    std::vector<double> omega( vertices.size(), 0.0 );
    std::vector<int> redundancy( vertices.size(), 0 );
    for ( size_t i = 0; i < vertices.size(); ++i )
    {
      LineVertex3d &v = vertices[i];
      if ( !( v.sigmaReferencePx > 0 ) || !( v.sigmaPartnerLinePx > 0 ) )
        continue;
      std::vector<Observation> observations;
      observations.push_back( { own.images[0].image, 0, true, v.pixelInReference, Eigen::Vector2d::Zero(), v.sigmaReferencePx, own.images[0].imageId } );
      observations.push_back( { own.images[1].image, 0, false, v.pixelInPartner, rightNormal( v.partnerLineDirection ), v.sigmaPartnerLinePx, own.images[1].imageId } );
      const Eigen::Vector3d tangent = tangentAt( vertices, i, lineDirection );
      int looks = 0; // other images the vertex is in, where the line was looked for

      // the line where the vertex projects into the other stations' images
      for ( size_t s = 0; s < others.size(); ++s )
      {
        if ( !rigs[s + 1].pose )
          continue;
        const Eigen::Matrix3d predicted = v.covariance + rigPoseCovariance( *rigs[s + 1].pose, v.point, rigs[s + 1].centre );
        for ( const StereoImage &image : others[s].images )
        {
          const Eigen::Vector3d camera = image.image->exterior().projectionCentre;
          const double range = ( v.point - camera ).head<2>().norm();
          if ( range > options.maxRangeM )
            continue;
          Eigen::Vector2d pixel;
          Eigen::Matrix<double, 2, 3> j;
          if ( !projectWithJacobian( *image.image, v.point, pixel, j ) )
            continue;
          const cv::Mat &grey = *image.grey;
          if ( pixel.x() < options.marginPx || pixel.y() < options.marginPx || pixel.x() > grey.cols - options.marginPx || pixel.y() > grey.rows - options.marginPx )
            continue;
          const Eigen::Vector2d along = j * tangent;
          if ( along.norm() < 1e-6 )
            continue;
          const Eigen::Vector2d direction = along.normalized(), normal = rightNormal( direction );
          LineProfile there = profile;
          if ( profile.kind != LineKind::Edge && widthTimesRange > 0 )
          {
            there.widthPx = widthTimesRange / std::max( range, 1.0 );
            if ( there.widthPx < options.minWidthPx )
              continue;
          }
          const double sigmaPredicted = std::sqrt( std::max( 0.0, double( normal.transpose() * j * predicted * j.transpose() * normal ) ) );
          const double searchHalf = std::clamp( 3.0 * sigmaPredicted, options.minSearchHalfPx, options.maxSearchHalfPx );
          ++looks;
          const std::optional<LineHit> hit = locateLine( grey, pixel, direction, there, locateOptionsFor( there, FollowOptions(), searchHalf ) );
          if ( !hit )
            continue;
          double sigmaHit = std::max( options.sigmaFloorPx, hit->sigmaPx );
          if ( options.lineSigmaM > 0 )
            sigmaHit = std::max( sigmaHit, options.lineSigmaM * pixelsPerMetreAcross( *image.image, v.point, tangent ) );
          const double offset = normal.dot( pixel - hit->pixelInImage );
          if ( std::abs( offset ) > options.gateW * std::hypot( sigmaPredicted, sigmaHit ) )
          {
            ++summary.rejected;
            continue;
          }
          observations.push_back( { image.image, s + 1, false, hit->pixelInImage, normal, sigmaHit, image.imageId } );
        }
      }
      unconfirmed[i] = looks >= options.minLooksToConfirm;
      if ( observations.size() <= 2 )
        continue;

      // adjust; the other stations' observation with the largest normalised residual beyond the gate goes, in turn
      Solution solution;
      while ( observations.size() > 2 )
      {
        solution = adjust( observations, rigs, v.point );
        if ( !solution.ok )
          break;
        size_t worst = 0;
        for ( size_t k = 2; k < observations.size(); ++k )
          if ( solution.normalised[k] > options.gateW && ( worst == 0 || solution.normalised[k] > solution.normalised[worst] ) )
            worst = k;
        if ( worst == 0 )
          break;
        observations.erase( observations.begin() + static_cast<std::ptrdiff_t>( worst ) );
        ++summary.rejected;
        solution.ok = false;
      }
      if ( !solution.ok || observations.size() <= 2 )
        continue;
      // the station's own pair disagrees with two or more observations from the others: a wrong conjugate
      if ( observations.size() >= 4 && std::max( solution.normalised[0], solution.normalised[1] ) > options.gateW )
      {
        drop[i] = true;
        ++summary.dropped;
        continue;
      }
      v.point = solution.point;
      v.covariance = solution.covariance;
      v.sigmaM = v.covariance.diagonal().cwiseMax( 0.0 ).cwiseSqrt();
      const auto projected = [&]( const Observation &o ) { return o.image->projectGroundToPixel( v.point ).pixelInImage; };
      v.residualReferencePx = projected( observations[0] ) - observations[0].pixel;
      v.residualPartnerPx = observations[1].normal * observations[1].normal.dot( projected( observations[1] ) - observations[1].pixel );
      v.others.clear();
      for ( size_t k = 2; k < observations.size(); ++k )
      {
        const Observation &o = observations[k];
        v.others.push_back( { o.imageId, o.pixel, o.normal * o.normal.dot( projected( o ) - o.pixel ) } );
      }
      ++summary.vertices;
      summary.observations += static_cast<int>( v.others.size() );
      omega[i] = solution.omega;
      redundancy[i] = solution.redundancy;
      // confirmed where the line is found in at least half of the other images that see the vertex
      confirmed[i] = 2 * static_cast<int>( v.others.size() ) >= looks;
      unconfirmed[i] = !confirmed[i] && looks >= options.minLooksToConfirm;
    }
    // a vertex the others looked for and did not find, where they found others of the station's vertices: not
    // confirmed, left out (the line runs on between its confirmed neighbours)
    if ( options.minLooksToConfirm > 0 && std::any_of( confirmed.begin(), confirmed.end(), []( bool c ) { return c; } ) )
      for ( size_t i = 0; i < vertices.size(); ++i )
        if ( unconfirmed[i] && !drop[i] )
        {
          drop[i] = true;
          ++summary.unconfirmed;
          if ( !vertices[i].others.empty() )
          {
            --summary.vertices;
            summary.observations -= static_cast<int>( vertices[i].others.size() );
          }
        }
    size_t kept = 0;
    for ( size_t i = 0; i < vertices.size(); ++i )
      if ( !drop[i] )
      {
        summary.weightedSquares += omega[i];
        summary.redundancy += redundancy[i];
        vertices[kept++] = vertices[i];
      }
    vertices.resize( kept );
    return summary;
  }

} // namespace geostation
