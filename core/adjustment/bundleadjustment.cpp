/***************************************************************************
  bundleadjustment.cpp - bundle adjustment of a block
 ***************************************************************************/
#include "adjustment/bundleadjustment.h"

#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include <Eigen/Dense>
#include <ceres/ceres.h>

#include "adjustment/collinearityerror.h"
#include "adjustment/intersection.h"
#include "adjustment/priors.h"
#include "adjustment/schurcovariance.h"
#include "geometry/projection.h"

namespace geostation
{

  namespace
  {
    struct PointState
    {
      std::string id;
      std::array<double, 3> local {};
      const ControlPoint *known = nullptr; //!< control or check point, or nullptr for a tie point
      std::vector<size_t> observations;    //!< indices into the observation list
      BundlePointResult::Role role = BundlePointResult::Role::Tie;
    };

    //! Hands every iteration to BundleOptions::onIteration; aborts the solve when it says stop.
    class IterationCallbackAdapter : public ceres::IterationCallback
    {
      public:
        explicit IterationCallbackAdapter( const std::function<bool( int, double )> &onIteration )
          : mOnIteration( onIteration ) {}

        ceres::CallbackReturnType operator()( const ceres::IterationSummary &iteration ) override
        {
          if ( mOnIteration && !mOnIteration( iteration.iteration, iteration.cost ) )
          {
            mStopped = true;
            return ceres::SOLVER_ABORT;
          }
          return ceres::SOLVER_CONTINUE;
        }

        bool stopped() const { return mStopped; }

      private:
        const std::function<bool( int, double )> &mOnIteration;
        bool mStopped = false;
    };

    BundleSummary failure( BundleSummary::Status status, const std::string &message )
    {
      BundleSummary s;
      s.status = status;
      s.message = message;
      return s;
    }

    std::array<double, 3> toArray( const Eigen::Vector3d &v ) { return { v.x(), v.y(), v.z() }; }
  } // namespace

  BundleSummary bundleAdjust( const std::vector<Camera> &cameras, const std::vector<BundleImage> &images, const std::vector<ControlPoint> &groundPoints,
                              const std::vector<BundleObservation> &observations, const BundleOptions &options )
  {
    // ---- preconditions ----
    std::map<std::string, size_t> cameraIndex, imageIndex;
    for ( size_t i = 0; i < cameras.size(); ++i )
    {
      cameras[i].validate();
      cameraIndex[cameras[i].id] = i;
      if ( cameras[i].distortion.model == DistortionModel::None )
        for ( int k = kInteriorK1; k < kInteriorSize; ++k )
          if ( options.freeInterior[k] )
            throw std::invalid_argument( std::string( "camera '" ) + cameras[i].id + "' has no lens model, so " + interiorParameterNames()[k] + " cannot be estimated" );
    }
    for ( size_t i = 0; i < images.size(); ++i )
    {
      if ( !cameraIndex.count( images[i].cameraId ) )
        throw std::invalid_argument( "image '" + images[i].id + "' uses camera '" + images[i].cameraId + "', which is not given" );
      imageIndex[images[i].id] = i;
    }
    for ( const BundleObservation &o : observations )
    {
      if ( !imageIndex.count( o.imageId ) )
        throw std::invalid_argument( "point '" + o.pointId + "' is observed in image '" + o.imageId + "', which is not in the adjustment" );
      if ( !( o.sigmaPx > 0.0 ) )
        throw std::invalid_argument( "point '" + o.pointId + "' in image '" + o.imageId + "': pixel sigma must be positive" );
    }

    // Local origin: the mean projection centre.
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    for ( const BundleImage &image : images )
      origin += image.exterior.projectionCentre;
    origin /= std::max<size_t>( 1, images.size() );

    std::vector<std::array<double, 6>> poses( images.size() );
    std::vector<std::array<double, kInteriorSize>> interiors( cameras.size() );
    std::vector<std::unique_ptr<OrientedImage>> startImages;
    for ( size_t i = 0; i < images.size(); ++i )
    {
      const ExteriorOrientation &eo = images[i].exterior;
      const Eigen::Vector3d c = eo.projectionCentre - origin;
      poses[i] = { c.x(), c.y(), c.z(), degToRad( eo.omegaDeg ), degToRad( eo.phiDeg ), degToRad( eo.kappaDeg ) };
      startImages.push_back( std::make_unique<OrientedImage>( cameras[cameraIndex[images[i].cameraId]], eo ) );
    }
    for ( size_t c = 0; c < cameras.size(); ++c )
      interiorBlockFromCamera( cameras[c], interiors[c].data() );

    // ---- points: control at their known position, tie and check points intersected ----
    std::map<std::string, const ControlPoint *> known;
    for ( const ControlPoint &g : groundPoints )
      known[g.id] = &g;
    std::map<std::string, std::vector<size_t>> observationsOfPoint;
    for ( size_t k = 0; k < observations.size(); ++k )
      observationsOfPoint[observations[k].pointId].push_back( k );

    BundleSummary summary;
    std::vector<PointState> points;
    points.reserve( observationsOfPoint.size() );
    for ( const auto &[id, obs] : observationsOfPoint )
    {
      PointState p;
      p.id = id;
      p.observations = obs;
      const auto it = known.find( id );
      if ( it != known.end() )
      {
        p.known = it->second;
        p.role = it->second->check ? BundlePointResult::Role::Check : BundlePointResult::Role::Control;
      }
      if ( p.role == BundlePointResult::Role::Control )
        p.local = toArray( p.known->world - origin );
      else
      {
        std::vector<RayObservation> rays;
        for ( size_t k : obs )
          rays.push_back( { startImages[imageIndex[observations[k].imageId]].get(), observations[k].pixelInImage, observations[k].sigmaPx } );
        const IntersectionSummary start = intersectRays( rays );
        if ( !start.ok() )
        {
          summary.skippedPoints.push_back( id );
          continue;
        }
        p.local = toArray( start.point - origin );
      }
      points.push_back( p );
    }

    // ---- datum ----
    int controlUsed = 0;
    bool anyPrior = false;
    for ( const PointState &p : points )
      controlUsed += p.role == BundlePointResult::Role::Control ? 1 : 0;
    if ( options.usePosePriors )
      for ( const BundleImage &image : images )
        anyPrior |= image.exterior.sigma.has_value();
    if ( !anyPrior && controlUsed < 3 )
      return failure( BundleSummary::Status::NoDatum, "the block has no datum: measure at least three control points or use the images' GNSS/INS orientation as priors" );

    // ---- problem ----
    ceres::Problem problem;
    std::map<const double *, std::vector<int>> fixedOf; //!< components held fixed, per block with a SubsetManifold
    ceres::LossFunction *loss = options.robust ? new ceres::HuberLoss( options.robustThreshold ) : nullptr;
    std::vector<bool> imageUsed( images.size(), false ), cameraUsed( cameras.size(), false );
    for ( PointState &p : points )
      for ( size_t k : p.observations )
      {
        const BundleObservation &o = observations[k];
        const size_t i = imageIndex[o.imageId];
        const size_t c = cameraIndex[images[i].cameraId];
        problem.AddResidualBlock( CollinearityError::create( cameras[c], o.pixelInImage.x(), o.pixelInImage.y(), o.sigmaPx ), loss,
                                  poses[i].data(), interiors[c].data(), p.local.data() );
        imageUsed[i] = cameraUsed[c] = true;
      }
    if ( problem.NumResidualBlocks() == 0 )
      return failure( BundleSummary::Status::TooFewObservations, "no point is observed often enough to take part (tie points need two images)" );

    for ( PointState &p : points )
      if ( p.role == BundlePointResult::Role::Control )
      {
        const std::array<double, 3> sigma = toArray( p.known->sigmaM );
        const std::vector<int> fixed = ParameterPrior<3>::fixedComponents( sigma );
        if ( fixed.size() == 3 )
          problem.SetParameterBlockConstant( p.local.data() );
        else
        {
          problem.AddResidualBlock( ParameterPrior<3>::create( toArray( p.known->world - origin ), sigma ), nullptr, p.local.data() );
          if ( !fixed.empty() )
          {
            problem.SetManifold( p.local.data(), new ceres::SubsetManifold( 3, fixed ) );
            fixedOf[p.local.data()] = fixed;
          }
        }
      }
    for ( size_t i = 0; i < images.size(); ++i )
    {
      if ( !imageUsed[i] || !options.usePosePriors || !images[i].exterior.sigma )
        continue;
      const ExteriorSigma &s = *images[i].exterior.sigma;
      const std::array<double, 6> sigma { s.x, s.y, s.z, degToRad( s.omegaDeg ), degToRad( s.phiDeg ), degToRad( s.kappaDeg ) };
      const std::vector<int> fixed = ParameterPrior<6>::fixedComponents( sigma );
      if ( fixed.size() == 6 )
        problem.SetParameterBlockConstant( poses[i].data() );
      else
      {
        problem.AddResidualBlock( ParameterPrior<6>::create( poses[i], sigma ), nullptr, poses[i].data() );
        if ( !fixed.empty() )
        {
          problem.SetManifold( poses[i].data(), new ceres::SubsetManifold( 6, fixed ) );
          fixedOf[poses[i].data()] = fixed;
        }
      }
    }
    std::vector<int> fixedInterior;
    for ( int k = 0; k < kInteriorSize; ++k )
      if ( !options.freeInterior[k] )
        fixedInterior.push_back( k );
    for ( size_t c = 0; c < cameras.size(); ++c )
    {
      if ( !cameraUsed[c] )
        continue;
      if ( fixedInterior.size() == kInteriorSize )
        problem.SetParameterBlockConstant( interiors[c].data() );
      else if ( !fixedInterior.empty() )
      {
        problem.SetManifold( interiors[c].data(), new ceres::SubsetManifold( kInteriorSize, fixedInterior ) );
        fixedOf[interiors[c].data()] = fixedInterior;
      }
    }

    // ---- solve ----
    ceres::Solver::Options solverOptions;
    solverOptions.linear_solver_type = images.size() <= 200 ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
    solverOptions.max_num_iterations = options.maxIterations;
    solverOptions.function_tolerance = 1e-12;
    solverOptions.gradient_tolerance = 1e-12;
    solverOptions.parameter_tolerance = 1e-12;
    solverOptions.num_threads = std::max( 1, options.threads );
    IterationCallbackAdapter callback( options.onIteration );
    if ( options.onIteration )
      solverOptions.callbacks.push_back( &callback );
    ceres::Solver::Summary solverSummary;
    ceres::Solve( solverOptions, &problem, &solverSummary );
    if ( callback.stopped() )
      return failure( BundleSummary::Status::Cancelled, "the bundle adjustment was cancelled after " + std::to_string( solverSummary.iterations.size() ) + " iteration(s)" );
    summary.iterations = static_cast<int>( solverSummary.iterations.size() );
    summary.solveSeconds = solverSummary.total_time_in_seconds;
    summary.converged = solverSummary.termination_type == ceres::CONVERGENCE;
    if ( solverSummary.termination_type == ceres::FAILURE )
      return failure( BundleSummary::Status::Failed, "the bundle adjustment failed: " + solverSummary.message );
    if ( !summary.converged )
      return failure( BundleSummary::Status::NotConverged, "the bundle adjustment did not converge in " + std::to_string( options.maxIterations ) + " iterations: " + solverSummary.message );

    // ---- statistics, without the robust loss ----
    ceres::Problem::EvaluateOptions evaluate;
    evaluate.apply_loss_function = false;
    double cost = 0.0;
    problem.Evaluate( evaluate, &cost, nullptr, nullptr, nullptr );
    summary.redundancy = static_cast<long>( solverSummary.num_residuals_reduced ) - static_cast<long>( solverSummary.num_effective_parameters_reduced );
    summary.sigma0 = summary.redundancy > 0 ? std::sqrt( 2.0 * cost / summary.redundancy ) : 0.0;
    const double varianceFactor = summary.redundancy > 0 ? summary.sigma0 * summary.sigma0 : 1.0;

    // Covariances through the Schur complement: cheap per point, exact.
    std::map<const double *, Eigen::MatrixXd> tangentCovariance;
    if ( options.computeCovariance )
    {
      std::vector<double *> cameraBlocks, pointBlocks;
      for ( size_t i = 0; i < images.size(); ++i )
        if ( imageUsed[i] && !problem.IsParameterBlockConstant( poses[i].data() ) )
          cameraBlocks.push_back( poses[i].data() );
      for ( size_t c = 0; c < cameras.size(); ++c )
        if ( cameraUsed[c] && !problem.IsParameterBlockConstant( interiors[c].data() ) )
          cameraBlocks.push_back( interiors[c].data() );
      for ( PointState &p : points )
        if ( !problem.IsParameterBlockConstant( p.local.data() ) )
          pointBlocks.push_back( p.local.data() );
      const SchurCovariance covariance = schurCovariance( problem, cameraBlocks, pointBlocks );
      if ( !covariance.ok )
        return failure( BundleSummary::Status::NoDatum, "the block's parameters are not all determined (the normal equations are singular); add control points, pose priors or tie points, or free fewer interior parameters" );
      for ( size_t b = 0; b < cameraBlocks.size(); ++b )
      {
        const int size = problem.ParameterBlockTangentSize( cameraBlocks[b] );
        tangentCovariance[cameraBlocks[b]] = covariance.cameras.block( covariance.cameraOffsets[b], covariance.cameraOffsets[b], size, size );
      }
      for ( size_t j = 0; j < pointBlocks.size(); ++j )
        tangentCovariance[pointBlocks[j]] = covariance.points[j];
    }
    // Standard deviations in the block's own coordinates; fixed components get 0.
    const auto sigmaOf = [&]( const double *block, int size ) -> Eigen::VectorXd
    {
      Eigen::VectorXd sigma = Eigen::VectorXd::Zero( size );
      const auto it = tangentCovariance.find( block );
      if ( it == tangentCovariance.end() )
        return sigma;
      const auto fixedIt = fixedOf.find( block );
      int t = 0;
      for ( int k = 0; k < size; ++k )
      {
        if ( fixedIt != fixedOf.end() && std::find( fixedIt->second.begin(), fixedIt->second.end(), k ) != fixedIt->second.end() )
          continue;
        sigma( k ) = std::sqrt( std::max( 0.0, it->second( t, t ) * varianceFactor ) );
        ++t;
      }
      return sigma;
    };

    // ---- residuals in pixels, per image and per point ----
    std::vector<double> imageSum( images.size(), 0.0 );
    std::vector<int> imageCount( images.size(), 0 );
    double totalSum = 0.0;
    long totalCount = 0;
    std::vector<double> pointRms( points.size(), 0.0 );
    for ( size_t j = 0; j < points.size(); ++j )
    {
      double pointSum = 0.0;
      for ( size_t k : points[j].observations )
      {
        const BundleObservation &o = observations[k];
        const size_t i = imageIndex[o.imageId];
        const size_t c = cameraIndex[images[i].cameraId];
        std::unique_ptr<ceres::CostFunction> costFunction( CollinearityError::create( cameras[c], o.pixelInImage.x(), o.pixelInImage.y(), o.sigmaPx ) );
        const double *parameters[3] = { poses[i].data(), interiors[c].data(), points[j].local.data() };
        double r[2];
        costFunction->Evaluate( parameters, r, nullptr );
        const double squaredPx = ( r[0] * r[0] + r[1] * r[1] ) * o.sigmaPx * o.sigmaPx;
        imageSum[i] += squaredPx;
        imageCount[i] += 1;
        pointSum += squaredPx;
        totalSum += squaredPx;
        ++totalCount;
      }
      pointRms[j] = std::sqrt( pointSum / ( 2.0 * points[j].observations.size() ) );
    }
    summary.rmsPx = totalCount ? std::sqrt( totalSum / ( 2.0 * totalCount ) ) : 0.0;

    for ( size_t i = 0; i < images.size(); ++i )
    {
      BundleImageResult r;
      r.id = images[i].id;
      r.exterior.projectionCentre = Eigen::Vector3d( poses[i][0], poses[i][1], poses[i][2] ) + origin;
      r.exterior.omegaDeg = radToDeg( poses[i][3] );
      r.exterior.phiDeg = radToDeg( poses[i][4] );
      r.exterior.kappaDeg = radToDeg( poses[i][5] );
      if ( imageUsed[i] )
      {
        const Eigen::VectorXd s = sigmaOf( poses[i].data(), 6 );
        r.exterior.sigma = ExteriorSigma { s( 0 ), s( 1 ), s( 2 ), radToDeg( s( 3 ) ), radToDeg( s( 4 ) ), radToDeg( s( 5 ) ) };
      }
      else
        r.exterior.sigma = images[i].exterior.sigma; // untouched
      r.observationCount = imageCount[i];
      r.rmsPx = imageCount[i] ? std::sqrt( imageSum[i] / ( 2.0 * imageCount[i] ) ) : 0.0;
      r.shiftM = r.exterior.projectionCentre - images[i].exterior.projectionCentre;
      summary.images.push_back( r );
    }
    for ( size_t c = 0; c < cameras.size(); ++c )
    {
      BundleCameraResult r;
      r.camera = cameras[c];
      cameraFromInteriorBlock( interiors[c].data(), &r.camera );
      const Eigen::VectorXd s = sigmaOf( interiors[c].data(), kInteriorSize );
      for ( int k = 0; k < kInteriorSize; ++k )
        if ( options.freeInterior[k] && cameraUsed[c] )
        {
          r.freeParameters.push_back( interiorParameterNames()[k] );
          r.sigmas.push_back( s( k ) );
        }
      summary.cameras.push_back( r );
    }
    Eigen::Vector3d sumControl = Eigen::Vector3d::Zero(), sumCheck = Eigen::Vector3d::Zero();
    for ( size_t j = 0; j < points.size(); ++j )
    {
      const PointState &p = points[j];
      BundlePointResult r;
      r.id = p.id;
      r.role = p.role;
      r.world = Eigen::Vector3d( p.local[0], p.local[1], p.local[2] ) + origin;
      r.sigmaM = sigmaOf( p.local.data(), 3 );
      r.imageCount = static_cast<int>( p.observations.size() );
      r.rmsPx = pointRms[j];
      if ( p.known )
      {
        r.errorM = r.world - p.known->world;
        if ( p.role == BundlePointResult::Role::Control )
        {
          sumControl += r.errorM.cwiseAbs2();
          ++summary.controlCount;
        }
        else
        {
          sumCheck += r.errorM.cwiseAbs2();
          ++summary.checkCount;
        }
      }
      summary.points.push_back( r );
    }
    if ( summary.controlCount )
      summary.rmseControlM = ( sumControl / summary.controlCount ).cwiseSqrt();
    if ( summary.checkCount )
      summary.rmseCheckM = ( sumCheck / summary.checkCount ).cwiseSqrt();
    if ( !summary.skippedPoints.empty() )
      summary.message = std::to_string( summary.skippedPoints.size() ) + " points seen in fewer than two images (or with parallel rays) were left out";
    return summary;
  }

} // namespace geostation
