/***************************************************************************
  pointmeasurer.cpp
 ***************************************************************************/
#include "workstation/pointmeasurer.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "dem/monoplotter.h"

namespace geostation
{

  namespace
  {
    std::vector<Eigen::Vector2d> curvePixels( const EpipolarCurve &curve )
    {
      std::vector<Eigen::Vector2d> pixels;
      for ( const auto &piece : curve.pieces )
        for ( const EpipolarVertex &v : piece )
          pixels.push_back( v.pixelInImage );
      return pixels;
    }

    //! The matching options for one view: the window's shape predicted from the surface, where it is known and the point is in the frame.
    AreaMatchOptions viewAreaOptions( const MeasurementView &reference, const Eigen::Vector2d &pixelInReference, const MeasurementView &view,
                                      const ProposalOptions &options )
    {
      AreaMatchOptions area = options.area;
      if ( !options.groundOfPixel )
        return area;
      // differences over a quarter of the window follow a curved DEM within the window
      const double step = std::max( 1.0, std::max( area.windowWidth, area.windowHeight ) / 4.0 );
      const std::optional<PredictedWindow> predicted = predictWindowShape( *reference.image, pixelInReference, *view.image, options.groundOfPixel, step );
      if ( predicted && view.pixels->canSample( predicted->pixelInSearch.x(), predicted->pixelInSearch.y() ) )
        area.predictedShape = predicted->searchFromReference;
      return area;
    }

  }

  std::vector<ConjugateProposal> proposeConjugates( const std::vector<MeasurementView> &views, size_t reference, const Eigen::Vector2d &pixelInReference,
      const ProposalOptions &options )
  {
    if ( reference >= views.size() || !views[reference].image )
      throw std::invalid_argument( "proposeConjugates: the reference view must exist and be oriented" );
    std::vector<ConjugateProposal> proposals( views.size() );
    std::vector<size_t> matchable;
    for ( size_t i = 0; i < views.size(); ++i )
    {
      ConjugateProposal &p = proposals[i];
      p.imageId = views[i].imageId;
      if ( i == reference )
        continue;
      if ( !views[i].image )
      {
        p.message = "the image is not oriented";
        continue;
      }
      p.curve = epipolarCurve( *views[reference].image, pixelInReference, *views[i].image, options.epipolar );
      for ( const auto &piece : p.curve.pieces )
        for ( const EpipolarVertex &v : piece )
          p.curveInFrame = p.curveInFrame || v.inFrame;
      if ( !p.curveInFrame )
        p.message = "the epipolar curve does not cross the image";
      else if ( !views[i].pixels || !views[reference].pixels )
        p.message = "the image cannot be read";
      else
        matchable.push_back( i );
    }

    // all views together first: a candidate must be confirmed in each
    bool together = false;
    if ( options.multiImage && matchable.size() >= 2 )
    {
      std::vector<MatchView> matchViews { MatchView { views[reference].image, views[reference].pixels } };
      for ( size_t i : matchable )
        matchViews.push_back( MatchView { views[i].image, views[i].pixels } );
      MultiImageMatchOptions multi;
      multi.area = options.area;
      multi.epipolar = options.epipolar;
      const MultiImageMatch m = matchMultiImage( matchViews, 0, 1, pixelInReference, multi );
      if ( m.matched() )
      {
        together = true;
        for ( size_t k = 0; k < matchable.size(); ++k )
        {
          ConjugateProposal &p = proposals[matchable[k]];
          if ( m.pixels[k + 1] )
          {
            p.status = MatchStatus::Correlation;
            p.pixelInImage = *m.pixels[k + 1];
            p.score = m.scores[k + 1];
            p.sigmaPx = 0.5;
          }
        }
      }
    }
    // then each view with the reference alone (also refines the multi-image positions by LSM)
    for ( size_t i : matchable )
    {
      ConjugateProposal &p = proposals[i];
      if ( together && !p.matched() )
        continue;
      const std::vector<Eigen::Vector2d> curve = curvePixels( p.curve );
      AreaMatchOptions area = viewAreaOptions( views[reference], pixelInReference, views[i], options );
      area.borderIsNoPeak = !together; // 1.5 px around the multi-image position refines it; it is no search
      const AreaMatch m = together
                          ? matchAroundPosition( *views[reference].pixels, pixelInReference, *views[i].pixels, p.pixelInImage, 1.5, area )
                          : matchAlongEpipolarBand( *views[reference].pixels, pixelInReference, *views[i].pixels, curve, area );
      if ( m.matched() )
      {
        p.status = m.status;
        p.pixelInImage = m.pixelInImage;
        p.score = m.score;
        p.sigmaPx = std::max( 0.02, m.sigmaPx );
      }
      else if ( !together )
      {
        p.status = m.status;
        p.message = m.message.empty() ? "no match" : m.message;
      }
      // the conjugate point of an oriented pair lies on the epipolar curve (within the band and the orientation's error)
      if ( p.matched() && !p.curve.pieces.empty() )
        if ( const double off = p.curve.distanceToCurvePx( p.pixelInImage ); off > options.maxEpipolarDistancePx )
        {
          p.status = MatchStatus::Inconsistent;
          p.message = "the match lies " + std::to_string( off ).substr( 0, 4 ) + " px from the epipolar curve";
        }
    }
    flagInconsistentProposals( views, reference, pixelInReference, options, proposals );
    return proposals;
  }

  void flagInconsistentProposals( const std::vector<MeasurementView> &views, size_t reference, const Eigen::Vector2d &pixelInReference,
                                  const ProposalOptions &options, std::vector<ConjugateProposal> &proposals )
  {
    while ( true )
    {
      // the operator's click defines the ray: held (nearly) fixed, so the disagreement shows in the proposals checked
      std::vector<RayObservation> rays { { views[reference].image, pixelInReference, 0.01 } };
      std::vector<size_t> of { reference };
      for ( size_t i = 0; i < proposals.size(); ++i )
        if ( i != reference && proposals[i].matched() )
        {
          rays.push_back( { views[i].image, proposals[i].pixelInImage, std::max( 0.1, proposals[i].sigmaPx ) } );
          of.push_back( i );
        }
      if ( rays.size() < 3 )
        return;
      const IntersectionSummary s = intersectRays( rays );
      if ( !s.ok() )
        return;
      size_t worst = 0;
      double worstPx = 0.0;
      for ( size_t k = 1; k < rays.size(); ++k )
      {
        const double px = s.residuals[k].residualPx.norm();
        if ( px > std::max( options.maxIntersectionResidualPx, 3.0 * rays[k].sigmaPx ) && px > worstPx )
        {
          worst = k;
          worstPx = px;
        }
      }
      if ( worst == 0 )
        return;
      const std::string px = std::to_string( worstPx ).substr( 0, 4 );
      if ( rays.size() == 3 )
      {
        // two proposals that disagree both lie on the reference ray's epipolar curves: which one is wrong
        // cannot be told, so neither is taken
        for ( size_t k = 1; k < 3; ++k )
        {
          ConjugateProposal &p = proposals[of[k]];
          p.status = MatchStatus::Inconsistent;
          p.message = "the proposals of two images disagree (" + px + " px in the intersection): confirm one by hand";
        }
        return;
      }
      ConjugateProposal &p = proposals[of[worst]];
      p.status = MatchStatus::Inconsistent;
      p.message = "the other images' rays meet " + px + " px from the match";
    }
  }

  std::string vertexMethodName( VertexMethod method )
  {
    switch ( method )
    {
      case VertexMethod::Intersection:
        return "intersection";
      case VertexMethod::MonoplotDem:
        return "monoplot-DEM";
      case VertexMethod::RoadPlane:
        return "road-plane";
    }
    return "intersection";
  }

  MeasuredVertex intersectVertex( const std::vector<VertexObservation> &observations, const IntersectionOptions &options )
  {
    MeasuredVertex v;
    v.method = VertexMethod::Intersection;
    std::vector<RayObservation> rays;
    for ( const VertexObservation &o : observations )
    {
      rays.push_back( RayObservation { o.image, o.pixelInImage, o.sigmaPx } );
      v.imageIds.push_back( o.imageId );
    }
    const IntersectionSummary s = intersectRays( rays, options );
    if ( !s.ok() )
    {
      v.message = s.message;
      return v;
    }
    v.status = MeasuredVertex::Status::Ok;
    v.point = s.point;
    v.sigmaM = s.sigmaM;
    v.rmsPx = s.rmsPx;
    v.maxRayAngleDeg = s.maxRayAngleDeg;
    v.rangeM = std::numeric_limits<double>::infinity();
    for ( size_t i = 0; i < s.residuals.size(); ++i )
    {
      v.residualsPx.push_back( s.residuals[i].residualPx );
      v.rangeM = std::min( v.rangeM, s.residuals[i].rangeM );
      if ( s.residuals[i].suspect && s.grossError )
      {
        v.status = MeasuredVertex::Status::Suspect;
        v.message = "The ray of " + observations[i].imageId + " may carry a gross error (normalised residual "
                    + std::to_string( s.residuals[i].normalised ).substr( 0, 4 ) + ").";
      }
    }
    return v;
  }

  namespace
  {
    //! A vertex from one ray (plane or DEM): its point, or why there is none.
    MeasuredVertex singleRayVertex( VertexMethod method, const VertexObservation &observation, bool ok, const Eigen::Vector3d &point,
                                    const Eigen::Vector3d &sigmaM, double rangeM, const std::string &failure )
    {
      MeasuredVertex v;
      v.method = method;
      v.imageIds = { observation.imageId };
      v.residualsPx = { Eigen::Vector2d::Zero() };
      v.status = ok ? MeasuredVertex::Status::Ok : MeasuredVertex::Status::MissesSurface;
      if ( !ok )
        v.message = failure;
      else
      {
        v.point = point;
        v.sigmaM = sigmaM;
        v.rangeM = rangeM;
      }
      return v;
    }
  }

  MeasuredVertex roadPlaneVertex( const VertexObservation &observation, double roadHeightM, double planeSigmaM )
  {
    const PlaneIntersectionSummary s = intersectRayWithPlane( RayObservation { observation.image, observation.pixelInImage, observation.sigmaPx },
                                       Plane::horizontal( roadHeightM ), planeSigmaM );
    return singleRayVertex( VertexMethod::RoadPlane, observation, s.ok(), s.point, s.sigmaM, s.rangeM, s.message );
  }

  MeasuredVertex demVertex( const VertexObservation &observation, const Monoplotter &monoplotter )
  {
    const MonoplotPoint p = monoplotter.imageToGround( observation.pixelInImage, true );
    return singleRayVertex( VertexMethod::MonoplotDem, observation, p.ok(), p.world, p.sigmaM, p.rangeM,
                            p.message.empty() ? "The ray does not meet the DEM." : p.message );
  }

  std::vector<MeasuredVertex> demVerticesBetween( const VertexObservation &from, const Eigen::Vector2d &toPixel, const Monoplotter &monoplotter, double stepPx )
  {
    if ( !( stepPx > 0.0 ) )
      throw std::invalid_argument( "The densification step must be positive." );
    const Eigen::Vector2d along = toPixel - from.pixelInImage;
    const int pieces = static_cast<int>( std::ceil( along.norm() / stepPx ) );
    std::vector<MeasuredVertex> between;
    for ( int k = 1; k < pieces; ++k )
    {
      VertexObservation at = from;
      at.pixelInImage = from.pixelInImage + along * ( static_cast<double>( k ) / pieces );
      const MeasuredVertex v = demVertex( at, monoplotter );
      if ( v.ok() )
        between.push_back( v );
    }
    return between;
  }

} // namespace geostation
