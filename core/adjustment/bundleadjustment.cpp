/***************************************************************************
  bundleadjustment.cpp - bundle adjustment of a block
  -------------------------------------------------------------------------
  BundleAdjuster runs the adjustment in named steps, as COLMAP's does:
  checkInput, setUpParameters, startPoints, checkDatum, buildProblem,
  solve, computeCovariances, then the results (residuals, images, cameras,
  points).
 ***************************************************************************/
#include "adjustment/bundleadjustment.h"

#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include <Eigen/Dense>
#include <ceres/ceres.h>

#include "adjustment/internal/collinearityerror.h"
#include "adjustment/intersection.h"
#include "adjustment/internal/priors.h"
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

    //! Reports every iteration to BundleOptions::progress; aborts the solve when the caller asks to stop.
    class IterationCallbackAdapter : public ceres::IterationCallback
    {
      public:
        IterationCallbackAdapter( const Progress &progress, int maxIterations )
          : mProgress( progress ), mMaxIterations( std::max( 1, maxIterations ) ) {}

        ceres::CallbackReturnType operator()( const ceres::IterationSummary &iteration ) override
        {
          if ( !mProgress.report( static_cast<double>( iteration.iteration ) / mMaxIterations,
                                  "iteration " + std::to_string( iteration.iteration ) + ", cost " + std::to_string( iteration.cost ) ) )
          {
            mStopped = true;
            return ceres::SOLVER_ABORT;
          }
          return ceres::SOLVER_CONTINUE;
        }

        bool stopped() const { return mStopped; }

      private:
        const Progress &mProgress;
        int mMaxIterations;
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

    //! One adjustment of a block (bundleAdjust()); the parameters live in it, relative to a local origin.
    class BundleAdjuster
    {
      public:
        BundleAdjuster( const std::vector<Camera> &cameras, const std::vector<BundleImage> &images, const std::vector<ControlPoint> &groundPoints,
                        const std::vector<BundleObservation> &observations, const BundleOptions &options )
          : mCameras( cameras ), mImages( images ), mGroundPoints( groundPoints ), mObservations( observations ), mOptions( options ) {}

        BundleSummary run();

      private:
        void checkInput();
        void setUpParameters();
        void startPoints();
        std::optional<BundleSummary> checkDatum() const;
        void addObservations();
        void addControl();
        void addPosePriors();
        void fixInterior();
        std::optional<BundleSummary> solve();
        bool computeCovariances();
        Eigen::VectorXd sigmaOf( const double *block, int size ) const;
        void collectResiduals();
        ExteriorOrientation adjustedExterior( size_t i ) const;
        void collectImages();
        void collectCameras();
        void collectPoints();
        void holdFixed( double *block, int size, const std::vector<int> &fixed );

        const std::vector<Camera> &mCameras;
        const std::vector<BundleImage> &mImages;
        const std::vector<ControlPoint> &mGroundPoints;
        const std::vector<BundleObservation> &mObservations;
        const BundleOptions &mOptions;

        std::map<std::string, size_t> mCameraIndex, mImageIndex;
        Eigen::Vector3d mOrigin = Eigen::Vector3d::Zero(); //!< the mean projection centre
        std::vector<std::array<double, 6>> mPoses;         //!< X, Y, Z - origin (m), omega, phi, kappa (rad)
        std::vector<std::array<double, kInteriorSize>> mInteriors;
        std::vector<std::unique_ptr<OrientedImage>> mStartImages;
        std::vector<PointState> mPoints;
        ceres::Problem mProblem;
        std::map<const double *, std::vector<int>> mFixedOf; //!< components held fixed, per block with a SubsetManifold
        std::vector<bool> mImageUsed, mCameraUsed;
        std::map<const double *, Eigen::MatrixXd> mTangentCovariance;
        double mVarianceFactor = 1.0;
        std::vector<double> mImageSumPx2, mPointRmsPx;
        std::vector<int> mImageCount;
        BundleSummary mSummary;
    };

    BundleSummary BundleAdjuster::run()
    {
      checkInput();
      setUpParameters();
      startPoints();
      if ( std::optional<BundleSummary> noDatum = checkDatum() )
        return *noDatum;
      addObservations();
      if ( mProblem.NumResidualBlocks() == 0 )
        return failure( BundleSummary::Status::TooFewObservations, "no point is observed often enough to take part (tie points need two images)" );
      addControl();
      addPosePriors();
      fixInterior();
      if ( std::optional<BundleSummary> failed = solve() )
        return *failed;
      if ( !computeCovariances() )
        return failure( BundleSummary::Status::NoDatum, "the block's parameters are not all determined (the normal equations are singular); add control points, pose priors or tie points, or free fewer interior parameters" );
      collectResiduals();
      collectImages();
      collectCameras();
      collectPoints();
      if ( !mSummary.skippedPoints.empty() )
        mSummary.message = std::to_string( mSummary.skippedPoints.size() ) + " points seen in fewer than two images (or with parallel rays) were left out";
      return std::move( mSummary );
    }

    //! Preconditions: valid cameras, known cameras and images, positive sigmas, free lens parameters only with a lens model.
    void BundleAdjuster::checkInput()
    {
      mOptions.check();
      for ( size_t i = 0; i < mCameras.size(); ++i )
      {
        mCameras[i].validate();
        mCameraIndex[mCameras[i].id] = i;
        if ( mCameras[i].distortion.model == DistortionModel::None )
          for ( int k = kInteriorK1; k < kInteriorSize; ++k )
            if ( mOptions.freeInterior[k] )
              throw std::invalid_argument( std::string( "camera '" ) + mCameras[i].id + "' has no lens model, so " + interiorParameterNames()[k] + " cannot be estimated" );
      }
      for ( size_t i = 0; i < mImages.size(); ++i )
      {
        if ( !mCameraIndex.count( mImages[i].cameraId ) )
          throw std::invalid_argument( "image '" + mImages[i].id + "' uses camera '" + mImages[i].cameraId + "', which is not given" );
        mImageIndex[mImages[i].id] = i;
      }
      for ( const BundleObservation &o : mObservations )
      {
        if ( !mImageIndex.count( o.imageId ) )
          throw std::invalid_argument( "point '" + o.pointId + "' is observed in image '" + o.imageId + "', which is not in the adjustment" );
        if ( !( o.sigmaPx > 0.0 ) )
          throw std::invalid_argument( "point '" + o.pointId + "' in image '" + o.imageId + "': pixel sigma must be positive" );
      }
      for ( const ControlPoint &c : mGroundPoints )
        checkPlausiblePosition( c );
    }

    //! Poses relative to the mean projection centre, interiors as blocks, and the start orientations for the points' first intersection.
    void BundleAdjuster::setUpParameters()
    {
      for ( const BundleImage &image : mImages )
        mOrigin += image.exterior.projectionCentre;
      mOrigin /= std::max<size_t>( 1, mImages.size() );
      mPoses.resize( mImages.size() );
      mInteriors.resize( mCameras.size() );
      for ( size_t i = 0; i < mImages.size(); ++i )
      {
        const ExteriorOrientation &eo = mImages[i].exterior;
        const Eigen::Vector3d c = eo.projectionCentre - mOrigin;
        mPoses[i] = { c.x(), c.y(), c.z(), degToRad( eo.omegaDeg ), degToRad( eo.phiDeg ), degToRad( eo.kappaDeg ) };
        mStartImages.push_back( std::make_unique<OrientedImage>( mCameras[mCameraIndex[mImages[i].cameraId]], eo ) );
      }
      for ( size_t c = 0; c < mCameras.size(); ++c )
        interiorBlockFromCamera( mCameras[c], mInteriors[c].data() );
      mImageUsed.assign( mImages.size(), false );
      mCameraUsed.assign( mCameras.size(), false );
    }

    //! Control points at their known position, tie and check points intersected from the start orientations (or skipped).
    void BundleAdjuster::startPoints()
    {
      std::map<std::string, const ControlPoint *> known;
      for ( const ControlPoint &g : mGroundPoints )
        known[g.id] = &g;
      std::map<std::string, std::vector<size_t>> observationsOfPoint;
      for ( size_t k = 0; k < mObservations.size(); ++k )
        observationsOfPoint[mObservations[k].pointId].push_back( k );
      mPoints.reserve( observationsOfPoint.size() );
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
          p.local = toArray( p.known->world - mOrigin );
        else
        {
          std::vector<RayObservation> rays;
          for ( size_t k : obs )
            rays.push_back( { mStartImages[mImageIndex[mObservations[k].imageId]].get(), mObservations[k].pixelInImage, mObservations[k].sigmaPx } );
          const IntersectionSummary start = intersectRays( rays );
          if ( !start.ok() )
          {
            mSummary.skippedPoints.push_back( id );
            continue;
          }
          p.local = toArray( start.point - mOrigin );
        }
        mPoints.push_back( p );
      }
    }

    //! Three control points or pose priors fix the block in space; otherwise the NoDatum failure.
    std::optional<BundleSummary> BundleAdjuster::checkDatum() const
    {
      int controlUsed = 0;
      bool anyPrior = false;
      for ( const PointState &p : mPoints )
        controlUsed += p.role == BundlePointResult::Role::Control ? 1 : 0;
      if ( mOptions.usePosePriors )
        for ( const BundleImage &image : mImages )
          anyPrior |= image.exterior.sigma.has_value();
      if ( !anyPrior && controlUsed < 3 )
        return failure( BundleSummary::Status::NoDatum, "the block has no datum: measure at least three control points or use the images' GNSS/INS orientation as priors" );
      return std::nullopt;
    }

    //! A collinearity residual per observation (with the Huber loss when robust).
    void BundleAdjuster::addObservations()
    {
      ceres::LossFunction *loss = mOptions.robust ? new ceres::HuberLoss( mOptions.robustThreshold ) : nullptr;
      for ( PointState &p : mPoints )
        for ( size_t k : p.observations )
        {
          const BundleObservation &o = mObservations[k];
          const size_t i = mImageIndex[o.imageId];
          const size_t c = mCameraIndex[mImages[i].cameraId];
          mProblem.AddResidualBlock( CollinearityError::create( mCameras[c], o.pixelInImage.x(), o.pixelInImage.y(), o.sigmaPx ), loss,
                                     mPoses[i].data(), mInteriors[c].data(), p.local.data() );
          mImageUsed[i] = mCameraUsed[c] = true;
        }
    }

    //! Components with sigma 0 held fixed (a SubsetManifold), recorded for the sigmas.
    void BundleAdjuster::holdFixed( double *block, int size, const std::vector<int> &fixed )
    {
      if ( fixed.empty() )
        return;
      mProblem.SetManifold( block, new ceres::SubsetManifold( size, fixed ) );
      mFixedOf[block] = fixed;
    }

    //! Control points: fixed, or weighted by their sigmas.
    void BundleAdjuster::addControl()
    {
      for ( PointState &p : mPoints )
      {
        if ( p.role != BundlePointResult::Role::Control )
          continue;
        const std::array<double, 3> sigma = toArray( p.known->sigmaM );
        const std::vector<int> fixed = ParameterPrior<3>::fixedComponents( sigma );
        if ( fixed.size() == 3 )
          mProblem.SetParameterBlockConstant( p.local.data() );
        else
        {
          mProblem.AddResidualBlock( ParameterPrior<3>::create( toArray( p.known->world - mOrigin ), sigma ), nullptr, p.local.data() );
          holdFixed( p.local.data(), 3, fixed );
        }
      }
    }

    //! The images' GNSS/INS orientations as observations, with their sigmas.
    void BundleAdjuster::addPosePriors()
    {
      if ( !mOptions.usePosePriors )
        return;
      for ( size_t i = 0; i < mImages.size(); ++i )
      {
        if ( !mImageUsed[i] || !mImages[i].exterior.sigma )
          continue;
        const ExteriorSigma &s = *mImages[i].exterior.sigma;
        const std::array<double, 6> sigma { s.x, s.y, s.z, degToRad( s.omegaDeg ), degToRad( s.phiDeg ), degToRad( s.kappaDeg ) };
        const std::vector<int> fixed = ParameterPrior<6>::fixedComponents( sigma );
        if ( fixed.size() == 6 )
          mProblem.SetParameterBlockConstant( mPoses[i].data() );
        else
        {
          mProblem.AddResidualBlock( ParameterPrior<6>::create( mPoses[i], sigma ), nullptr, mPoses[i].data() );
          holdFixed( mPoses[i].data(), 6, fixed );
        }
      }
    }

    //! The interior parameters not freed for self-calibration held fixed.
    void BundleAdjuster::fixInterior()
    {
      std::vector<int> fixedInterior;
      for ( int k = 0; k < kInteriorSize; ++k )
        if ( !mOptions.freeInterior[k] )
          fixedInterior.push_back( k );
      for ( size_t c = 0; c < mCameras.size(); ++c )
      {
        if ( !mCameraUsed[c] )
          continue;
        if ( fixedInterior.size() == kInteriorSize )
          mProblem.SetParameterBlockConstant( mInteriors[c].data() );
        else
          holdFixed( mInteriors[c].data(), kInteriorSize, fixedInterior );
      }
    }

    //! Levenberg-Marquardt with the Schur complement; the failure (cancelled, failed, not converged), or nothing; then sigma0 without the robust loss.
    std::optional<BundleSummary> BundleAdjuster::solve()
    {
      ceres::Solver::Options solverOptions;
      solverOptions.linear_solver_type = static_cast<int>( mImages.size() ) <= mOptions.denseSchurMaxImages ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
      solverOptions.max_num_iterations = mOptions.maxIterations;
      solverOptions.function_tolerance = mOptions.functionTolerance;
      solverOptions.gradient_tolerance = mOptions.gradientTolerance;
      solverOptions.parameter_tolerance = mOptions.parameterTolerance;
      solverOptions.num_threads = std::max( 1, mOptions.threads );
      IterationCallbackAdapter callback( mOptions.progress, mOptions.maxIterations );
      solverOptions.callbacks.push_back( &callback );
      ceres::Solver::Summary solverSummary;
      ceres::Solve( solverOptions, &mProblem, &solverSummary );
      if ( callback.stopped() )
        return failure( BundleSummary::Status::Cancelled, "the bundle adjustment was cancelled after " + std::to_string( solverSummary.iterations.size() ) + " iteration(s)" );
      mSummary.iterations = static_cast<int>( solverSummary.iterations.size() );
      mSummary.solveSeconds = solverSummary.total_time_in_seconds;
      mSummary.converged = solverSummary.termination_type == ceres::CONVERGENCE;
      if ( solverSummary.termination_type == ceres::FAILURE )
        return failure( BundleSummary::Status::Failed, "the bundle adjustment failed: " + solverSummary.message );
      if ( !mSummary.converged )
        return failure( BundleSummary::Status::NotConverged, "the bundle adjustment did not converge in " + std::to_string( mOptions.maxIterations ) + " iterations: " + solverSummary.message );

      ceres::Problem::EvaluateOptions evaluate;
      evaluate.apply_loss_function = false;
      double cost = 0.0;
      mProblem.Evaluate( evaluate, &cost, nullptr, nullptr, nullptr );
      mSummary.redundancy = static_cast<long>( solverSummary.num_residuals_reduced ) - static_cast<long>( solverSummary.num_effective_parameters_reduced );
      mSummary.sigma0 = mSummary.redundancy > 0 ? std::sqrt( 2.0 * cost / mSummary.redundancy ) : 0.0;
      mVarianceFactor = mSummary.redundancy > 0 ? mSummary.sigma0 * mSummary.sigma0 : 1.0;
      return std::nullopt;
    }

    //! Covariances through the Schur complement: cheap per point, exact. False when the normal equations are singular.
    bool BundleAdjuster::computeCovariances()
    {
      if ( !mOptions.computeCovariance )
        return true;
      std::vector<double *> cameraBlocks, pointBlocks;
      for ( size_t i = 0; i < mImages.size(); ++i )
        if ( mImageUsed[i] && !mProblem.IsParameterBlockConstant( mPoses[i].data() ) )
          cameraBlocks.push_back( mPoses[i].data() );
      for ( size_t c = 0; c < mCameras.size(); ++c )
        if ( mCameraUsed[c] && !mProblem.IsParameterBlockConstant( mInteriors[c].data() ) )
          cameraBlocks.push_back( mInteriors[c].data() );
      for ( PointState &p : mPoints )
        if ( !mProblem.IsParameterBlockConstant( p.local.data() ) )
          pointBlocks.push_back( p.local.data() );
      const SchurCovariance covariance = schurCovariance( mProblem, cameraBlocks, pointBlocks );
      if ( !covariance.ok )
        return false;
      for ( size_t b = 0; b < cameraBlocks.size(); ++b )
      {
        const int size = mProblem.ParameterBlockTangentSize( cameraBlocks[b] );
        mTangentCovariance[cameraBlocks[b]] = covariance.cameras.block( covariance.cameraOffsets[b], covariance.cameraOffsets[b], size, size );
      }
      for ( size_t j = 0; j < pointBlocks.size(); ++j )
        mTangentCovariance[pointBlocks[j]] = covariance.points[j];
      return true;
    }

    //! Standard deviations in the block's own coordinates, scaled by sigma0; fixed components get 0.
    Eigen::VectorXd BundleAdjuster::sigmaOf( const double *block, int size ) const
    {
      Eigen::VectorXd sigma = Eigen::VectorXd::Zero( size );
      const auto it = mTangentCovariance.find( block );
      if ( it == mTangentCovariance.end() )
        return sigma;
      const auto fixedIt = mFixedOf.find( block );
      int t = 0;
      for ( int k = 0; k < size; ++k )
      {
        if ( fixedIt != mFixedOf.end() && std::find( fixedIt->second.begin(), fixedIt->second.end(), k ) != fixedIt->second.end() )
          continue;
        sigma( k ) = std::sqrt( std::max( 0.0, it->second( t, t ) * mVarianceFactor ) );
        ++t;
      }
      return sigma;
    }

    //! Residuals in pixels: each observation's (the adjusted point projected through the adjusted image, minus the measurement), sums per image, RMS per point and overall.
    void BundleAdjuster::collectResiduals()
    {
      mImageSumPx2.assign( mImages.size(), 0.0 );
      mImageCount.assign( mImages.size(), 0 );
      mPointRmsPx.assign( mPoints.size(), 0.0 );
      std::vector<Camera> cameras = mCameras;
      for ( size_t c = 0; c < cameras.size(); ++c )
        cameraFromInteriorBlock( mInteriors[c].data(), &cameras[c] );
      std::vector<std::unique_ptr<OrientedImage>> adjusted( mImages.size() );
      for ( size_t i = 0; i < mImages.size(); ++i )
        if ( mImageUsed[i] )
          adjusted[i] = std::make_unique<OrientedImage>( cameras[mCameraIndex[mImages[i].cameraId]], adjustedExterior( i ) );
      double totalSum = 0.0;
      long totalCount = 0;
      for ( size_t j = 0; j < mPoints.size(); ++j )
      {
        double pointSum = 0.0;
        const Eigen::Vector3d world = Eigen::Vector3d( mPoints[j].local[0], mPoints[j].local[1], mPoints[j].local[2] ) + mOrigin;
        for ( size_t k : mPoints[j].observations )
        {
          const BundleObservation &o = mObservations[k];
          const size_t i = mImageIndex[o.imageId];
          const GroundProjection g = adjusted[i]->projectGroundToPixel( world );
          Eigen::Vector2d residual = g.pixelInImage - o.pixelInImage;
          if ( !g.ok() )
          {
            // a point behind its image after the adjustment: the residual of the collinearity equations
            const size_t c = mCameraIndex[mImages[i].cameraId];
            std::unique_ptr<ceres::CostFunction> costFunction( CollinearityError::create( mCameras[c], o.pixelInImage.x(), o.pixelInImage.y(), o.sigmaPx ) );
            const double *parameters[3] = { mPoses[i].data(), mInteriors[c].data(), mPoints[j].local.data() };
            double r[2];
            costFunction->Evaluate( parameters, r, nullptr );
            residual = Eigen::Vector2d( r[0], r[1] ) * o.sigmaPx;
          }
          mSummary.observations.push_back( { mPoints[j].id, o.imageId, o.pixelInImage, residual } );
          const double squaredPx = residual.squaredNorm();
          mImageSumPx2[i] += squaredPx;
          mImageCount[i] += 1;
          pointSum += squaredPx;
          totalSum += squaredPx;
          ++totalCount;
        }
        mPointRmsPx[j] = std::sqrt( pointSum / ( 2.0 * mPoints[j].observations.size() ) );
      }
      mSummary.rmsPx = totalCount ? std::sqrt( totalSum / ( 2.0 * totalCount ) ) : 0.0;
    }

    ExteriorOrientation BundleAdjuster::adjustedExterior( size_t i ) const
    {
      ExteriorOrientation e;
      e.projectionCentre = Eigen::Vector3d( mPoses[i][0], mPoses[i][1], mPoses[i][2] ) + mOrigin;
      e.omegaDeg = radToDeg( mPoses[i][3] );
      e.phiDeg = radToDeg( mPoses[i][4] );
      e.kappaDeg = radToDeg( mPoses[i][5] );
      return e;
    }

    void BundleAdjuster::collectImages()
    {
      for ( size_t i = 0; i < mImages.size(); ++i )
      {
        BundleImageResult r;
        r.id = mImages[i].id;
        r.exterior = adjustedExterior( i );
        if ( mImageUsed[i] )
        {
          const Eigen::VectorXd s = sigmaOf( mPoses[i].data(), 6 );
          r.exterior.sigma = ExteriorSigma { s( 0 ), s( 1 ), s( 2 ), radToDeg( s( 3 ) ), radToDeg( s( 4 ) ), radToDeg( s( 5 ) ) };
        }
        else
          r.exterior.sigma = mImages[i].exterior.sigma; // untouched
        r.observationCount = mImageCount[i];
        r.rmsPx = mImageCount[i] ? std::sqrt( mImageSumPx2[i] / ( 2.0 * mImageCount[i] ) ) : 0.0;
        r.shiftM = r.exterior.projectionCentre - mImages[i].exterior.projectionCentre;
        mSummary.images.push_back( r );
      }
    }

    void BundleAdjuster::collectCameras()
    {
      for ( size_t c = 0; c < mCameras.size(); ++c )
      {
        BundleCameraResult r;
        r.camera = mCameras[c];
        cameraFromInteriorBlock( mInteriors[c].data(), &r.camera );
        const Eigen::VectorXd s = sigmaOf( mInteriors[c].data(), kInteriorSize );
        for ( int k = 0; k < kInteriorSize; ++k )
          if ( mOptions.freeInterior[k] && mCameraUsed[c] )
          {
            r.freeParameters.push_back( interiorParameterNames()[k] );
            r.sigmas.push_back( s( k ) );
          }
        mSummary.cameras.push_back( r );
      }
    }

    //! Points with sigmas and residuals; control and check points' errors against their known positions.
    void BundleAdjuster::collectPoints()
    {
      Eigen::Vector3d sumControl = Eigen::Vector3d::Zero(), sumCheck = Eigen::Vector3d::Zero();
      for ( size_t j = 0; j < mPoints.size(); ++j )
      {
        const PointState &p = mPoints[j];
        BundlePointResult r;
        r.id = p.id;
        r.role = p.role;
        r.world = Eigen::Vector3d( p.local[0], p.local[1], p.local[2] ) + mOrigin;
        r.sigmaM = sigmaOf( p.local.data(), 3 );
        r.imageCount = static_cast<int>( p.observations.size() );
        r.rmsPx = mPointRmsPx[j];
        if ( p.known )
        {
          r.errorM = r.world - p.known->world;
          const bool control = p.role == BundlePointResult::Role::Control;
          ( control ? sumControl : sumCheck ) += r.errorM.cwiseAbs2();
          ++( control ? mSummary.controlCount : mSummary.checkCount );
        }
        mSummary.points.push_back( r );
      }
      if ( mSummary.controlCount )
        mSummary.rmseControlM = ( sumControl / mSummary.controlCount ).cwiseSqrt();
      if ( mSummary.checkCount )
        mSummary.rmseCheckM = ( sumCheck / mSummary.checkCount ).cwiseSqrt();
    }
  } // namespace

  void BundleOptions::check() const
  {
    if ( maxIterations < 1 )
      throw std::invalid_argument( "the bundle adjustment needs at least one iteration" );
    if ( robust && !( robustThreshold > 0 && std::isfinite( robustThreshold ) ) )
      throw std::invalid_argument( "the robust threshold must be a positive number of sigmas" );
    for ( const double tolerance : { functionTolerance, gradientTolerance, parameterTolerance } )
      if ( !( tolerance > 0 && tolerance < 1 ) )
        throw std::invalid_argument( "the solver's tolerances must lie between 0 and 1" );
    if ( denseSchurMaxImages < 0 )
      throw std::invalid_argument( "the largest block for the dense Schur solver must be 0 images or more" );
  }

  BundleSummary bundleAdjust( const std::vector<Camera> &cameras, const std::vector<BundleImage> &images, const std::vector<ControlPoint> &groundPoints,
                              const std::vector<BundleObservation> &observations, const BundleOptions &options )
  {
    return BundleAdjuster( cameras, images, groundPoints, observations, options ).run();
  }

} // namespace geostation
