/***************************************************************************
  controlprediction.cpp - the semi-automatic mode: predicted control found
 ***************************************************************************/
#include "identification/controlprediction.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <Eigen/SVD>
#include <opencv2/imgproc.hpp>

#include "geometry/projection.h"

namespace geostation
{

  void ControlPredictionOptions::check() const
  {
    if ( !( searchRadiusPx >= 3.0 ) )
      throw std::invalid_argument( "the search radius around a predicted control point must be at least 3 px" );
    marks.check();
    if ( !( minRedundancy >= 0.0 && minRedundancy < 1.0 ) )
      throw std::invalid_argument( "the smallest redundancy number of a found point must be 0-1" );
    if ( !( sigmaPx > 0.0 ) || !( flagResidualPx > 0.0 ) || !( flagNormalised > 0.0 ) )
      throw std::invalid_argument( "the mark sigma and the flagging thresholds must be positive" );
    if ( !( ambiguityRatio >= 1.0 ) )
      throw std::invalid_argument( "the ambiguity ratio must be at least 1" );
  }

  std::string predictedPointStatusName( PredictedPoint::Status status )
  {
    switch ( status )
    {
      case PredictedPoint::Status::Found:
        return "found";
      case PredictedPoint::Status::Flagged:
        return "flagged";
      case PredictedPoint::Status::NotFound:
        return "not_found";
      case PredictedPoint::Status::Outside:
        return "outside";
    }
    return "not_found";
  }

  cv::Mat nominalImage( const cv::Mat &scanGrey, const Camera &camera, const Eigen::Matrix<double, 2, 3> &nominalFromScan )
  {
    if ( scanGrey.empty() || scanGrey.type() != CV_8UC1 )
      throw std::invalid_argument( "a scan is resampled from an 8-bit grey image" );
    cv::Mat affine( 2, 3, CV_64F ), nominal;
    for ( int r = 0; r < 2; ++r )
      for ( int c = 0; c < 3; ++c )
        affine.at<double>( r, c ) = nominalFromScan( r, c );
    // pixel centres are at +0.5 in both frames (docs/conventions.md §1); OpenCV's are at integers
    affine.at<double>( 0, 2 ) += 0.5 * ( nominalFromScan( 0, 0 ) + nominalFromScan( 0, 1 ) ) - 0.5;
    affine.at<double>( 1, 2 ) += 0.5 * ( nominalFromScan( 1, 0 ) + nominalFromScan( 1, 1 ) ) - 0.5;
    cv::warpAffine( scanGrey, nominal, affine, cv::Size( camera.width, camera.height ), cv::INTER_CUBIC, cv::BORDER_CONSTANT, cv::Scalar( 0 ) );
    return nominal;
  }

  namespace
  {
    /**
     * The centre of gravity of a mark's excess over half its contrast, recentred until it settles (at most
     * `rounds` times). Each region takes a pixel's offset from the current centre: `inMark` gives the mark's
     * peak (its 90th percentile), `inBackground` the background (its darker fifth), `weighed` the pixels whose
     * excess is weighed. Nothing when the window (`halfWindowPx` each way) leaves the image, the mark has no
     * contrast, or its centre walks further than `reachPx` from `approximate`.
     */
    template <typename Mark, typename Background, typename Weighed>
    std::optional<Eigen::Vector2d> settledCentreOfGravity( const cv::Mat &grey, const Eigen::Vector2d &approximate, bool brightMark, int rounds, int halfWindowPx,
        double reachPx, Mark inMark, Background inBackground, Weighed weighed, double *areaPx )
    {
      const double sign = brightMark ? 1.0 : -1.0;
      Eigen::Vector2d centre = approximate;
      for ( int round = 0; round < rounds; ++round )
      {
        const int half = halfWindowPx;
        const int c0 = static_cast<int>( std::floor( centre.x() ) ) - half, r0 = static_cast<int>( std::floor( centre.y() ) ) - half;
        if ( c0 < 0 || r0 < 0 || c0 + 2 * half + 1 > grey.cols || r0 + 2 * half + 1 > grey.rows )
          return std::nullopt;
        std::vector<double> around, inside;
        for ( int r = r0; r <= r0 + 2 * half; ++r )
          for ( int c = c0; c <= c0 + 2 * half; ++c )
          {
            const Eigen::Vector2d offset = Eigen::Vector2d( c + 0.5, r + 0.5 ) - centre;
            const double v = sign * grey.at<uint8_t>( r, c );
            if ( inMark( offset ) )
              inside.push_back( v );
            else if ( inBackground( offset ) )
              around.push_back( v );
          }
        if ( inside.empty() || around.empty() )
          return std::nullopt;
        std::sort( around.begin(), around.end() );
        std::sort( inside.begin(), inside.end() );
        const double background = around[around.size() / 5], peak = inside[inside.size() * 9 / 10];
        if ( peak - background < 5.0 )
          return std::nullopt;
        const double threshold = background + 0.5 * ( peak - background );
        double sum = 0.0, sx = 0.0, sy = 0.0, area = 0.0;
        for ( int r = r0; r <= r0 + 2 * half; ++r )
          for ( int c = c0; c <= c0 + 2 * half; ++c )
          {
            const Eigen::Vector2d at( c + 0.5, r + 0.5 );
            if ( !weighed( at - centre ) )
              continue;
            const double excess = std::min( sign * grey.at<uint8_t>( r, c ), peak ) - threshold;
            if ( excess <= 0.0 )
              continue;
            area += 1.0;
            sum += excess;
            sx += excess * at.x();
            sy += excess * at.y();
          }
        if ( !( sum > 0.0 ) )
          return std::nullopt;
        const Eigen::Vector2d next( sx / sum, sy / sum );
        if ( ( next - approximate ).norm() > reachPx )
          return std::nullopt; // walked off onto something else
        const bool settled = ( next - centre ).norm() < 0.01;
        centre = next;
        if ( areaPx )
          *areaPx = area;
        if ( settled )
          break;
      }
      return centre;
    }
  } // namespace

  std::optional<Eigen::Vector2d> markCentre( const cv::Mat &grey, const Eigen::Vector2d &approximate, double diameterPx, bool brightMark, double *areaPx )
  {
    if ( grey.empty() || grey.type() != CV_8UC1 || !approximate.allFinite() || !( diameterPx > 0.0 ) )
      return std::nullopt;
    // the mark: a round window of its size; the background: the darker part of a window that reaches over the mark's surround
    const double markRadius = 0.5 * diameterPx + 0.75;
    const auto inMark = [&]( const Eigen::Vector2d &offset ) { return offset.norm() <= markRadius; };
    const auto inBackground = [&]( const Eigen::Vector2d & ) { return true; };
    const auto weighed = [&]( const Eigen::Vector2d &offset ) { return offset.norm() <= markRadius + 1.0; };
    return settledCentreOfGravity( grey, approximate, brightMark, 3, static_cast<int>( std::ceil( 0.9 * diameterPx ) ) + 1, diameterPx, inMark, inBackground, weighed, areaPx );
  }

  std::optional<Eigen::Vector2d> markCentreInEllipse( const cv::Mat &grey, const Eigen::Vector2d &approximate, const Eigen::Matrix2d &discShape, bool brightMark, double *areaPx )
  {
    if ( grey.empty() || grey.type() != CV_8UC1 || !approximate.allFinite() || !discShape.allFinite() || std::abs( discShape.determinant() ) < 1e-9 )
      return std::nullopt;
    const Eigen::Matrix2d unitFromPixel = discShape.inverse();
    const double major = Eigen::JacobiSVD<Eigen::Matrix2d>( discShape ).singularValues()( 0 );
    // the mark: the disc grown by 1 px all round, no further than its black square (a target's square is 1.6 times
    // the disc's radius across, on the ground); the background: the darker part of the square around the disc.
    // A pixel's distance from the outline, in pixels, as the disc's own units grow with the direction (first order):
    const auto beyondOutlinePx = [&]( const Eigen::Vector2d &offset )
    {
      const Eigen::Vector2d u = unitFromPixel * offset;
      const double d = u.norm();
      if ( d < 1e-9 )
        return -1.0 / ( unitFromPixel.transpose() * Eigen::Vector2d::UnitX() ).norm();
      return ( d - 1.0 ) / ( unitFromPixel.transpose() * ( u / d ) ).norm();
    };
    const auto inSquare = [&]( const Eigen::Vector2d &offset ) { return ( unitFromPixel * offset ).cwiseAbs().maxCoeff() <= 1.6; };
    const auto inMark = [&]( const Eigen::Vector2d &offset ) { return beyondOutlinePx( offset ) <= 1.0 && inSquare( offset ); };
    const auto inBackground = [&]( const Eigen::Vector2d &offset ) { return inSquare( offset ); };
    const int half = static_cast<int>( std::ceil( 1.6 * std::sqrt( 2.0 ) * major + 2.0 ) ); // the whole black square
    return settledCentreOfGravity( grey, approximate, brightMark, 5, half, major, inMark, inBackground, inMark, areaPx );
  }

  namespace
  {
    //! The mark nearest `predicted` in a window around it; flags a second one almost as near.
    void findNear( const cv::Mat &grey, const Eigen::Vector2d &predicted, const ControlPredictionOptions &options, PredictedPoint &point )
    {
      MarkCandidateOptions marks = options.marks;
      marks.maxDiameterPx = largestMarkPx( options.marks, grey.size() ); // the whole photo's, not the window's
      marks.maxCandidates = std::max( marks.maxCandidates, 10 );
      const int r = static_cast<int>( std::ceil( options.searchRadiusPx + marks.maxDiameterPx ) );
      const cv::Rect window = cv::Rect( static_cast<int>( predicted.x() ) - r, static_cast<int>( predicted.y() ) - r, 2 * r + 1, 2 * r + 1 ) & cv::Rect( 0, 0, grey.cols, grey.rows );
      point.status = PredictedPoint::Status::NotFound;
      if ( window.width < 8 || window.height < 8 )
      {
        point.reason = "the window around the prediction leaves the image";
        return;
      }
      std::vector<std::pair<double, MarkCandidate>> near;
      for ( MarkCandidate m : detectMarkCandidates( grey( window ).clone(), marks ) )
      {
        m.pixelInImage += Eigen::Vector2d( window.x, window.y );
        const double d = ( m.pixelInImage - predicted ).norm();
        if ( d <= options.searchRadiusPx )
          near.emplace_back( d, m );
      }
      if ( near.empty() )
      {
        point.reason = "no mark within " + std::to_string( static_cast<int>( options.searchRadiusPx ) ) + " px of the prediction";
        return;
      }
      std::sort( near.begin(), near.end(), []( const auto &a, const auto &b ) { return a.first < b.first; } );
      const MarkCandidate &best = near.front().second;
      point.pixelInImage = markCentre( grey, best.pixelInImage, best.diameterPx, marks.brightMark ).value_or( best.pixelInImage );
      point.diameterPx = best.diameterPx;
      point.status = PredictedPoint::Status::Found;
      if ( near.size() > 1 && near[1].first < options.ambiguityRatio * std::max( 2.0, near.front().first ) )
      {
        point.status = PredictedPoint::Status::Flagged;
        point.reason = "a second mark is almost as near the prediction";
      }
    }
  } // namespace

  namespace
  {
    //! d(pixel) / d(ground X, Y) at a ground point, by finite differences of 0.1 m.
    std::optional<Eigen::Matrix2d> groundJacobian( const OrientedImage &oriented, const Eigen::Vector3d &world )
    {
      const GroundProjection at = oriented.projectGroundToPixel( world ), east = oriented.projectGroundToPixel( world + Eigen::Vector3d( 0.1, 0, 0 ) ),
                             north = oriented.projectGroundToPixel( world + Eigen::Vector3d( 0, 0.1, 0 ) );
      if ( !at.ok() || !east.ok() || !north.ok() )
        return std::nullopt;
      Eigen::Matrix2d j;
      j.col( 0 ) = ( east.pixelInImage - at.pixelInImage ) / 0.1;
      j.col( 1 ) = ( north.pixelInImage - at.pixelInImage ) / 0.1;
      return j;
    }

    /**
     * Where the centre of gravity of a level disc's image lies from the
     * image of its centre: perspective draws it toward the nearer side, by
     * up to half a pixel on a target 60 px across seen obliquely. The
     * centroid of the projected outline (72 points), less the projected
     * centre; nothing where the outline does not project.
     */
    std::optional<Eigen::Vector2d> discCentroidOffset( const OrientedImage &oriented, const Eigen::Vector3d &world, double radiusM )
    {
      const GroundProjection centre = oriented.projectGroundToPixel( world );
      if ( !centre.ok() || !( radiusM > 0.0 ) )
        return std::nullopt;
      std::vector<Eigen::Vector2d> outline;
      for ( int k = 0; k < 72; ++k )
      {
        const double angle = k * M_PI / 36.0;
        const GroundProjection g = oriented.projectGroundToPixel( world + radiusM * Eigen::Vector3d( std::cos( angle ), std::sin( angle ), 0.0 ) );
        if ( !g.ok() )
          return std::nullopt;
        outline.push_back( g.pixelInImage );
      }
      double area = 0.0;
      Eigen::Vector2d moment = Eigen::Vector2d::Zero();
      for ( size_t i = 0; i < outline.size(); ++i )
      {
        const Eigen::Vector2d &p = outline[i], &q = outline[( i + 1 ) % outline.size()];
        const double cross = p.x() * q.y() - q.x() * p.y();
        area += cross;
        moment += ( p + q ) * cross;
      }
      if ( std::abs( area ) < 1e-9 )
        return std::nullopt;
      return Eigen::Vector2d( moment / ( 3.0 * area ) - centre.pixelInImage );
    }
  } // namespace

  namespace
  {
    //! The operator's points and the found marks (with the flagged ones if `withFlagged`), for the resection.
    std::vector<ImagePoint> observationsOf( const std::vector<ImagePoint> &measured, const std::map<std::string, PredictedPoint> &points, bool withFlagged, double sigmaPx )
    {
      std::vector<ImagePoint> observations = measured;
      for ( const auto &[id, p] : points )
        if ( p.status == PredictedPoint::Status::Found || ( withFlagged && p.status == PredictedPoint::Status::Flagged ) )
          observations.push_back( { id, p.pixelInImage, sigmaPx } );
      return observations;
    }

    /**
     * Each point's prediction and residual from the orientation; a found mark the resection rejects, or leaves
     * further off than the thresholds, is flagged. Returns how many were flagged now.
     */
    int flagUnsupported( std::map<std::string, PredictedPoint> &points, const ResectionSummary &resection, const OrientedImage &oriented,
                         const std::vector<ControlPoint> &control, const ControlPredictionOptions &options )
    {
      std::map<std::string, const PointResidual *> residuals;
      for ( const PointResidual &r : resection.residuals )
        residuals[r.pointId] = &r;
      int flagged = 0;
      for ( const ControlPoint &c : control )
      {
        auto it = points.find( c.id );
        if ( it == points.end() )
          continue;
        PredictedPoint &point = it->second;
        const GroundProjection g = oriented.projectGroundToPixel( c.world );
        point.predictedPx = g.ok() ? g.pixelInImage : point.predictedPx;
        if ( point.status != PredictedPoint::Status::Found && point.status != PredictedPoint::Status::Flagged )
          continue;
        point.residualPx = point.predictedPx - point.pixelInImage;
        const auto r = residuals.find( c.id );
        point.normalised = r != residuals.end() ? r->second->normalised : 0.0;
        const bool blunder = r != residuals.end() && r->second->blunder;
        // a mark the other points hardly check (a low redundancy number: alone in a corner of the photo) pulls the
        // orientation to itself, wrong or right; the resection cannot vouch for it
        const bool unchecked = r != residuals.end() && r->second->redundancy < options.minRedundancy;
        if ( point.status == PredictedPoint::Status::Found &&
             ( blunder || unchecked || point.residualPx.norm() > options.flagResidualPx || std::abs( point.normalised ) > options.flagNormalised ) )
        {
          point.status = PredictedPoint::Status::Flagged;
          point.reason = blunder ? "the resection rejects it as a blunder"
                         : unchecked ? "the other points hardly check it (redundancy " + std::to_string( r->second->redundancy ).substr( 0, 4 ) + ")"
                                     : "the resection leaves " + std::to_string( point.residualPx.norm() ).substr( 0, 4 ) + " px on it";
          ++flagged;
        }
      }
      return flagged;
    }
  } // namespace

  ControlPredictionSummary predictAndFindControl( const cv::Mat &grey, const Camera &camera, const ExteriorOrientation &approximate,
      const std::vector<ControlPoint> &control, const std::vector<ImagePoint> &measured, const ControlPredictionOptions &options )
  {
    options.check();
    camera.validate();
    if ( grey.empty() || grey.type() != CV_8UC1 )
      throw std::invalid_argument( "control points are looked for in an 8-bit grey image" );
    if ( grey.cols != camera.width || grey.rows != camera.height )
      throw std::invalid_argument( "the image is " + std::to_string( grey.cols ) + " x " + std::to_string( grey.rows ) + " px but its camera " + camera.id + " is " +
                                   std::to_string( camera.width ) + " x " + std::to_string( camera.height ) );
    std::set<std::string> measuredIds;
    for ( const ImagePoint &m : measured )
      measuredIds.insert( m.pointId );

    ControlPredictionSummary summary;
    std::map<std::string, PredictedPoint> points;
    ExteriorOrientation orientation = approximate;
    ResectionOptions resectionOptions;
    resectionOptions.robust = true;
    resectionOptions.removeBlunders = true;
    for ( int round = 0; round < 2; ++round )
    {
      const OrientedImage oriented( camera, orientation );
      // after the first resection the predictions are good to a fraction of a pixel: each mark is then located at its
      // prediction, with the size the marks found so far have on the ground (their area over the ground-to-image scale)
      std::vector<double> groundRadii;
      if ( round == 1 )
        for ( const ControlPoint &c : control )
        {
          const auto it = points.find( c.id );
          if ( it == points.end() || it->second.status != PredictedPoint::Status::Found )
            continue;
          double area = 0.0;
          const std::optional<Eigen::Matrix2d> j = groundJacobian( oriented, c.world );
          if ( j && markCentre( grey, it->second.pixelInImage, it->second.diameterPx, options.marks.brightMark, &area ) && area > 0.0 )
            groundRadii.push_back( std::sqrt( area / ( M_PI * std::abs( j->determinant() ) ) ) );
        }
      std::sort( groundRadii.begin(), groundRadii.end() );
      for ( const ControlPoint &c : control )
      {
        if ( measuredIds.count( c.id ) )
          continue;
        PredictedPoint &point = points[c.id];
        point.pointId = c.id;
        const GroundProjection g = oriented.projectGroundToPixel( c.world );
        if ( !g.ok() || !g.inFrame )
        {
          point.status = PredictedPoint::Status::Outside;
          point.reason = g.ok() ? "predicted outside the frame" : "behind the camera or outside the lens field";
          continue;
        }
        if ( round == 0 )
        {
          findNear( grey, g.pixelInImage, options, point );
          continue;
        }
        if ( groundRadii.size() < 2 )
        {
          if ( point.status == PredictedPoint::Status::NotFound )
            findNear( grey, g.pixelInImage, options, point ); // looked for again around the better prediction
          continue;
        }
        const std::optional<Eigen::Matrix2d> j = groundJacobian( oriented, c.world );
        const double radius = groundRadii[groundRadii.size() / 2];
        const double diameter = j ? 2.0 * radius * Eigen::JacobiSVD<Eigen::Matrix2d>( *j ).singularValues()( 0 ) : 0.0;
        // (a level disc's area: one on a slope facing away from the camera covers less, down to a third on the
        // simulated hills; one facing it more)
        const double expectedArea = j ? M_PI * radius * radius * std::abs( j->determinant() ) : 0.0;
        const auto ofItsSize = [&]( const std::optional<Eigen::Vector2d> &at, double area )
        { return at && ( *at - g.pixelInImage ).norm() <= options.refineTolerancePx && area >= 0.3 * expectedArea && area <= 2.5 * expectedArea + 2.0; };
        // the mark in a round window, centred within its predicted outline where that agrees within 1 px (a long
        // ellipse seen at a grazing angle: the round window takes in what lies beside it). Within the outline alone
        // where the round window finds nothing of the mark's size was tried: it "finds" partly hidden marks, whose
        // centre the outline put at the prediction, and so claims what nobody can see
        // (ControlPrediction.PredictedControlFoundAndFlaggedOnSimulatedPhotos)
        double area = 0.0;
        std::optional<Eigen::Vector2d> centre = diameter >= 1.0 ? markCentre( grey, g.pixelInImage, diameter, options.marks.brightMark, &area ) : std::nullopt;
        if ( j && ofItsSize( centre, area ) )
          if ( const std::optional<Eigen::Vector2d> inOutline = markCentreInEllipse( grey, *centre, radius * *j, options.marks.brightMark ) )
            if ( ( *inOutline - *centre ).norm() <= 1.0 )
              centre = inOutline;
        if ( ofItsSize( centre, area ) )
        {
          // the disc's centre, not its image's centre of gravity
          Eigen::Vector2d discCentre = *centre;
          if ( const std::optional<Eigen::Vector2d> offset = discCentroidOffset( oriented, c.world, radius ) )
            discCentre -= *offset;
          point.status = PredictedPoint::Status::Found; // at the prediction: a second mark nearby no longer leaves a doubt
          point.pixelInImage = discCentre;
          point.reason.clear();
        }
        else if ( point.status == PredictedPoint::Status::Found )
        {
          point.status = PredictedPoint::Status::Flagged;
          point.reason = "no mark of the expected size at the prediction";
        }
        else if ( point.status == PredictedPoint::Status::NotFound )
          point.reason = "no mark of the expected size at the prediction";
      }
      // the operator's points and every mark found, robustly; what the resection rejects is flagged. The
      // first round takes the flagged ones too (a second mark nearby may be the better prediction's); the
      // final orientation only the operator's and the found ones: a flagged one waits for the operator
      resectionOptions.initial = orientation;
      summary.resection = resectImage( camera, control, observationsOf( measured, points, round == 0, options.sigmaPx ), resectionOptions );
      if ( !summary.resection.ok() )
        break;
      orientation = summary.resection.exterior;
    }

    // a found mark the final orientation leaves far off is flagged, and the orientation taken again without it
    // (at most twice); every point's residual is then that of the orientation reported
    for ( int pass = 0; summary.resection.ok(); ++pass )
    {
      if ( flagUnsupported( points, summary.resection, OrientedImage( camera, orientation ), control, options ) == 0 || pass == 2 )
        break;
      resectionOptions.initial = orientation;
      const ResectionSummary again = resectImage( camera, control, observationsOf( measured, points, false, options.sigmaPx ), resectionOptions );
      if ( !again.ok() )
        break;
      summary.resection = again;
      orientation = again.exterior;
    }
    for ( const ControlPoint &c : control )
    {
      auto it = points.find( c.id );
      if ( it == points.end() )
        continue;
      const PredictedPoint &point = it->second;
      switch ( point.status )
      {
        case PredictedPoint::Status::Found:
          ++summary.found;
          break;
        case PredictedPoint::Status::Flagged:
          ++summary.flagged;
          break;
        case PredictedPoint::Status::NotFound:
          ++summary.notFound;
          break;
        case PredictedPoint::Status::Outside:
          ++summary.outside;
          break;
      }
      summary.points.push_back( point );
    }
    summary.message = summary.resection.ok() ? std::to_string( summary.found ) + " control points found, " + std::to_string( summary.flagged ) + " flagged for review, " +
                      std::to_string( summary.notFound ) + " not found" : summary.resection.message;
    return summary;
  }

} // namespace geostation
