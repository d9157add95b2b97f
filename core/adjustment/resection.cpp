/***************************************************************************
  resection.cpp - space resection of one image from control points
  -------------------------------------------------------------------------
  Resector runs it in named steps: checkInput, pairControl, checkControl,
  startPose, solveRemovingBlunders, then fillEstimates and fillResiduals.
 ***************************************************************************/
#include "adjustment/resection.h"

#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <ceres/ceres.h>
#include <opencv2/calib3d.hpp>

#include "adjustment/internal/collinearityerror.h"
#include "adjustment/intersection.h"
#include "adjustment/internal/priors.h"
#include "geometry/projection.h"

namespace geostation
{

  namespace
  {
    //! A control point in use: its observation and its parameter block.
    struct UsedPoint
    {
      const ControlPoint *control;
      const ImagePoint *observation;
      std::array<double, 3> local; //!< the parameter block, relative to the origin
      bool free;                   //!< has a prior (sigma > 0 on every axis)
      Eigen::Vector3d knownLocal = Eigen::Vector3d::Zero(); //!< the known position, relative to the origin
    };

    ResectionSummary failure( ResectionSummary::Status status, const std::string &message )
    {
      ResectionSummary s;
      s.status = status;
      s.message = message;
      return s;
    }

    std::string freeList( const std::array<bool, kInteriorSize> &freeInterior )
    {
      std::string out;
      for ( int k = 0; k < kInteriorSize; ++k )
        if ( freeInterior[k] )
          out += std::string( out.empty() ? "" : ", " ) + interiorParameterNames()[k];
      return out;
    }

    //! Closed-form start: SQPnP on the undistorted rays of the control.
    std::optional<std::array<double, 6>> initialPose( const Camera &camera, const std::vector<UsedPoint> &points )
    {
      std::vector<cv::Point3d> objectPoints;
      std::vector<cv::Point2d> imagePoints;
      for ( const UsedPoint &p : points )
      {
        const std::optional<Eigen::Vector3d> ray = camera.rayInCameraFromPixel( p.observation->pixelInImage );
        if ( !ray )
          continue;
        objectPoints.emplace_back( p.local[0], p.local[1], p.local[2] );
        imagePoints.emplace_back( ray->x(), -ray->y() ); // OpenCV: y down
      }
      if ( objectPoints.size() < 4 )
        return std::nullopt;
      cv::Mat rvec, tvec;
      bool solved = false;
      try
      {
        solved = cv::solvePnP( objectPoints, imagePoints, cv::Matx33d::eye(), cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_SQPNP );
      }
      catch ( const cv::Exception & )
      {
        solved = false;
      }
      if ( !solved )
        return std::nullopt;
      cv::Matx33d rotationCv;
      cv::Rodrigues( rvec, rotationCv );
      Eigen::Matrix3d cvFromWorld;
      for ( int r = 0; r < 3; ++r )
        for ( int c = 0; c < 3; ++c )
          cvFromWorld( r, c ) = rotationCv( r, c );
      const Eigen::Vector3d t( tvec.at<double>( 0 ), tvec.at<double>( 1 ), tvec.at<double>( 2 ) );
      // Ours: x right, y up, z back = diag(1, -1, -1) * OpenCV's.
      const Eigen::Matrix3d worldFromCamera = cvFromWorld.transpose() * Eigen::DiagonalMatrix<double, 3>( 1, -1, -1 );
      const Eigen::Vector3d centre = -cvFromWorld.transpose() * t;
      const Eigen::Vector3d opk = omegaPhiKappaDegFromRotation( worldFromCamera );
      return std::array<double, 6> { centre.x(), centre.y(), centre.z(), degToRad( opk.x() ), degToRad( opk.y() ), degToRad( opk.z() ) };
    }

    bool allInFront( const std::array<double, 6> &pose, const std::vector<UsedPoint> &points )
    {
      const Eigen::Matrix3d R = worldFromCameraRotationDeg( radToDeg( pose[3] ), radToDeg( pose[4] ), radToDeg( pose[5] ) );
      for ( const UsedPoint &p : points )
        if ( !( ( R.transpose() * ( Eigen::Vector3d( p.local[0], p.local[1], p.local[2] ) - Eigen::Vector3d( pose[0], pose[1], pose[2] ) ) ).z() < 0.0 ) )
          return false;
      return true;
    }

    struct Solution
    {
      std::array<double, 6> pose;
      std::array<double, kInteriorSize> interior;
      ceres::Solver::Summary solverSummary;
      Eigen::MatrixXd jacobian;   //!< whitened, free parameters only
      Eigen::VectorXd residuals;  //!< whitened
      std::vector<int> interiorColumns; //!< interior index of each free interior column
    };

    /**
     * Builds and solves the problem; then evaluates the whitened Jacobian over
     * the free parameters (pose, free interior, free points) without loss.
     */
    Solution solve( const Camera &camera, std::vector<UsedPoint> &points, const std::array<double, 6> &startPose, const ResectionOptions &options )
    {
      Solution sol;
      sol.pose = startPose;
      interiorBlockFromCamera( camera, sol.interior.data() );

      ceres::Problem problem;
      ceres::LossFunction *loss = options.robust ? new ceres::HuberLoss( options.robustThreshold ) : nullptr;
      for ( UsedPoint &p : points )
      {
        problem.AddResidualBlock( CollinearityError::create( camera, p.observation->pixelInImage.x(), p.observation->pixelInImage.y(), p.observation->sigmaPx ),
                                 loss, sol.pose.data(), sol.interior.data(), p.local.data() );
        if ( p.free )
          problem.AddResidualBlock( ParameterPrior<3>::create( { p.knownLocal.x(), p.knownLocal.y(), p.knownLocal.z() }, { p.control->sigmaM.x(), p.control->sigmaM.y(), p.control->sigmaM.z() } ),
                                    nullptr, p.local.data() );
        else
          problem.SetParameterBlockConstant( p.local.data() );
      }
      std::vector<int> fixedInterior;
      for ( int k = 0; k < kInteriorSize; ++k )
        if ( !options.freeInterior[k] )
          fixedInterior.push_back( k );
        else
          sol.interiorColumns.push_back( k );
      if ( fixedInterior.size() == kInteriorSize )
        problem.SetParameterBlockConstant( sol.interior.data() );
      else if ( !fixedInterior.empty() )
        problem.SetManifold( sol.interior.data(), new ceres::SubsetManifold( kInteriorSize, fixedInterior ) );

      ceres::Solver::Options solverOptions;
      solverOptions.linear_solver_type = ceres::DENSE_QR;
      solverOptions.max_num_iterations = options.maxIterations;
      solverOptions.function_tolerance = options.functionTolerance;
      solverOptions.gradient_tolerance = options.gradientTolerance;
      solverOptions.parameter_tolerance = options.parameterTolerance;
      solverOptions.num_threads = 1;
      ceres::Solve( solverOptions, &problem, &sol.solverSummary );

      // Whitened Jacobian over the free parameters, from each cost function;
      // rows: two per observation, then three per point prior.
      const int freePoints = static_cast<int>( std::count_if( points.begin(), points.end(), []( const UsedPoint & p ) { return p.free; } ) );
      const int interiorColumns = static_cast<int>( sol.interiorColumns.size() );
      const int columns = 6 + interiorColumns + 3 * freePoints;
      const int observationRows = 2 * static_cast<int>( points.size() );
      sol.jacobian = Eigen::MatrixXd::Zero( observationRows + 3 * freePoints, columns );
      sol.residuals = Eigen::VectorXd::Zero( observationRows + 3 * freePoints );
      int freeIndex = 0;
      for ( size_t i = 0; i < points.size(); ++i )
      {
        UsedPoint &p = points[i];
        const int row = 2 * static_cast<int>( i );
        std::unique_ptr<ceres::CostFunction> cost( CollinearityError::create( camera, p.observation->pixelInImage.x(), p.observation->pixelInImage.y(), p.observation->sigmaPx ) );
        const double *parameters[3] = { sol.pose.data(), sol.interior.data(), p.local.data() };
        Eigen::Matrix<double, 2, 6, Eigen::RowMajor> jPose;
        Eigen::Matrix<double, 2, kInteriorSize, Eigen::RowMajor> jInterior;
        Eigen::Matrix<double, 2, 3, Eigen::RowMajor> jPoint;
        double *jacobians[3] = { jPose.data(), jInterior.data(), jPoint.data() };
        double r[2];
        cost->Evaluate( parameters, r, jacobians );
        sol.residuals.segment<2>( row ) = Eigen::Vector2d( r[0], r[1] );
        sol.jacobian.block<2, 6>( row, 0 ) = jPose;
        for ( int c = 0; c < interiorColumns; ++c )
          sol.jacobian.block<2, 1>( row, 6 + c ) = jInterior.col( sol.interiorColumns[c] );
        if ( p.free )
        {
          const int column = 6 + interiorColumns + 3 * freeIndex;
          const int priorRow = observationRows + 3 * freeIndex;
          sol.jacobian.block<2, 3>( row, column ) = jPoint;
          sol.jacobian.block<3, 3>( priorRow, column ) = p.control->sigmaM.cwiseInverse().asDiagonal();
          sol.residuals.segment<3>( priorRow ) = ( Eigen::Vector3d( p.local[0], p.local[1], p.local[2] ) - p.knownLocal ).cwiseQuotient( p.control->sigmaM );
          ++freeIndex;
        }
      }
      return sol;
    }

    //! One resection (resectImage()) in named steps; parameters relative to the centroid of the control.
    class Resector
    {
      public:
        Resector( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<ImagePoint> &observations, const ResectionOptions &options )
          : mCamera( camera ), mControl( control ), mObservations( observations ), mOptions( options ) {}

        ResectionSummary run();

      private:
        void checkInput();
        void pairControl();
        std::optional<ResectionSummary> checkControl();
        std::optional<ResectionSummary> startPose();
        std::optional<ResectionSummary> solveRemovingBlunders();
        std::optional<ResectionSummary> checkDeterminable( const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> &eigen ) const;
        void fillEstimates();
        void fillResiduals();

        const Camera &mCamera;
        const std::vector<ControlPoint> &mControl;
        const std::vector<ImagePoint> &mObservations;
        const ResectionOptions &mOptions;

        std::map<std::string, const ImagePoint *> mObserved;
        std::vector<UsedPoint> mUsed, mChecks;         //!< control in the adjustment; check points and removed blunders
        int mMinimum = 4;                              //!< control points needed
        Eigen::Vector3d mOrigin = Eigen::Vector3d::Zero();
        std::array<double, 6> mPose {};                //!< start of the next solve
        Solution mSolution;
        Eigen::MatrixXd mCofactor;
        Eigen::VectorXd mW;                            //!< Baarda's w per used point
        Eigen::VectorXd mRedundancy;                   //!< the smaller redundancy number of each used point's two coordinates
        std::vector<PointResidual> mRemoved;           //!< blunders, worst first
        ResectionSummary mSummary;
    };

    ResectionSummary Resector::run()
    {
      checkInput();
      pairControl();
      if ( std::optional<ResectionSummary> failed = checkControl() )
        return *failed;
      if ( std::optional<ResectionSummary> failed = startPose() )
        return *failed;
      if ( std::optional<ResectionSummary> failed = solveRemovingBlunders() )
        return *failed;
      mSummary.iterations = static_cast<int>( mSolution.solverSummary.iterations.size() );
      mSummary.converged = mSolution.solverSummary.termination_type == ceres::CONVERGENCE;
      if ( !mSummary.converged )
        return failure( ResectionSummary::Status::NotConverged, "the resection did not converge in " + std::to_string( mOptions.maxIterations ) + " iterations: " + mSolution.solverSummary.message );
      fillEstimates();
      fillResiduals();
      return std::move( mSummary );
    }

    //! Preconditions: a valid camera, lens parameters freed only with a lens model, positive sigmas, each point measured once.
    void Resector::checkInput()
    {
      mOptions.check();
      mCamera.validate();
      if ( mCamera.distortion.model == DistortionModel::None )
        for ( int k = kInteriorK1; k < kInteriorSize; ++k )
          if ( mOptions.freeInterior[k] )
            throw std::invalid_argument( std::string( "camera '" ) + mCamera.id + "' has no lens model, so " + interiorParameterNames()[k] + " cannot be estimated" );
      for ( const ImagePoint &o : mObservations )
      {
        if ( !( o.sigmaPx > 0.0 ) )
          throw std::invalid_argument( "point '" + o.pointId + "': pixel sigma must be positive" );
        if ( !mObserved.emplace( o.pointId, &o ).second )
          throw std::invalid_argument( "point '" + o.pointId + "' is measured twice in the image" );
      }
      for ( const ControlPoint &c : mControl )
        checkPlausiblePosition( c );
    }

    //! The control points measured in the image, used or check; the image points without control counted.
    void Resector::pairControl()
    {
      std::set<std::string> controlIds;
      for ( const ControlPoint &c : mControl )
      {
        controlIds.insert( c.id );
        const auto it = mObserved.find( c.id );
        if ( it == mObserved.end() )
          continue;
        UsedPoint p { &c, it->second, {}, !c.check && ( c.sigmaM.array() > 0.0 ).all() };
        ( c.check ? mChecks : mUsed ).push_back( p );
      }
      for ( const ImagePoint &o : mObservations )
        mSummary.unmatchedObservations += controlIds.count( o.pointId ) ? 0 : 1;
    }

    //! Enough control for the unknowns, not on one line; the local origin at its centroid.
    std::optional<ResectionSummary> Resector::checkControl()
    {
      int freeCount = 0;
      for ( bool f : mOptions.freeInterior )
        freeCount += f ? 1 : 0;
      mMinimum = std::max( 4, ( 6 + freeCount ) / 2 + 1 );
      if ( static_cast<int>( mUsed.size() ) < mMinimum )
      {
        std::ostringstream m;
        m << "a resection" << ( freeCount ? " with " + freeList( mOptions.freeInterior ) + " free" : std::string() ) << " needs at least " << mMinimum
          << " control points measured in the image; " << mUsed.size() << " given";
        return failure( ResectionSummary::Status::TooFewPoints, m.str() );
      }
      for ( const UsedPoint &p : mUsed )
        mOrigin += p.control->world;
      mOrigin /= static_cast<double>( mUsed.size() );
      const auto localise = [this]( UsedPoint & p )
      {
        p.knownLocal = p.control->world - mOrigin;
        p.local = { p.knownLocal.x(), p.knownLocal.y(), p.knownLocal.z() };
      };
      std::for_each( mUsed.begin(), mUsed.end(), localise );
      std::for_each( mChecks.begin(), mChecks.end(), localise );

      Eigen::MatrixXd centred( mUsed.size(), 3 );
      for ( size_t i = 0; i < mUsed.size(); ++i )
        centred.row( i ) = Eigen::Vector3d( mUsed[i].local[0], mUsed[i].local[1], mUsed[i].local[2] ).transpose();
      const Eigen::Vector3d singular = Eigen::JacobiSVD<Eigen::MatrixXd>( centred ).singularValues();
      if ( !( singular( 1 ) > 1e-3 * singular( 0 ) ) )
        return failure( ResectionSummary::Status::DegenerateControl, "the control points lie (nearly) on one line, which cannot fix the image's rotation about it; add control off that line" );
      return std::nullopt;
    }

    //! The given start, or the closed-form one; it must put the control in front of the camera.
    std::optional<ResectionSummary> Resector::startPose()
    {
      if ( const std::optional<ExteriorOrientation> &initial = mOptions.initial )
      {
        const Eigen::Vector3d c = initial->projectionCentre - mOrigin;
        mPose = { c.x(), c.y(), c.z(), degToRad( initial->omegaDeg ), degToRad( initial->phiDeg ), degToRad( initial->kappaDeg ) };
        return std::nullopt;
      }
      const std::optional<std::array<double, 6>> start = initialPose( mCamera, mUsed );
      if ( !start || !allInFront( *start, mUsed ) )
        return failure( ResectionSummary::Status::NoSolution, "no orientation puts the control points in front of the camera; check the point identifications and coordinates" );
      mPose = *start;
      return std::nullopt;
    }

    //! Solves; removes the worst blunder (Baarda's w) and solves again while one is found and enough control remains.
    std::optional<ResectionSummary> Resector::solveRemovingBlunders()
    {
      for ( ;; )
      {
        mSolution = solve( mCamera, mUsed, mPose, mOptions );
        const Solution &sol = mSolution;
        if ( sol.solverSummary.termination_type == ceres::FAILURE || !allInFront( sol.pose, mUsed ) )
          return failure( ResectionSummary::Status::NoSolution, "the adjustment failed: " + sol.solverSummary.message );
        // degeneracy: the column-scaled normal matrix must be well conditioned
        const Eigen::VectorXd scale = sol.jacobian.colwise().norm().cwiseMax( 1e-300 ).cwiseInverse();
        const Eigen::MatrixXd scaled = sol.jacobian * scale.asDiagonal();
        if ( std::optional<ResectionSummary> degenerate = checkDeterminable( Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>( scaled.transpose() * scaled ) ) )
          return degenerate;
        const Eigen::MatrixXd normal = sol.jacobian.transpose() * sol.jacobian;
        mCofactor = normal.inverse();
        const Eigen::VectorXd qvv = ( Eigen::MatrixXd::Identity( sol.jacobian.rows(), sol.jacobian.rows() ) - sol.jacobian * mCofactor * sol.jacobian.transpose() ).diagonal();
        mW = Eigen::VectorXd::Zero( mUsed.size() );
        mRedundancy = Eigen::VectorXd::Ones( mUsed.size() );
        for ( size_t i = 0; i < mUsed.size(); ++i )
          for ( int k = 0; k < 2; ++k )
          {
            mRedundancy( i ) = std::min( mRedundancy( i ), std::max( 0.0, qvv( 2 * i + k ) ) );
            if ( qvv( 2 * i + k ) > 1e-12 )
              mW( i ) = std::max( mW( i ), std::abs( sol.residuals( 2 * i + k ) ) / std::sqrt( qvv( 2 * i + k ) ) );
          }

        Eigen::Index worst = 0;
        const double worstW = mUsed.empty() ? 0.0 : mW.maxCoeff( &worst );
        if ( !( mOptions.removeBlunders && worstW > mOptions.blunderThreshold && static_cast<int>( mUsed.size() ) > mMinimum ) )
          return std::nullopt;
        PointResidual blunder;
        blunder.pointId = mUsed[worst].control->id;
        blunder.normalised = worstW;
        blunder.blunder = true;
        mRemoved.push_back( blunder );
        mChecks.push_back( mUsed[worst] ); // evaluated like a check point
        mUsed.erase( mUsed.begin() + worst );
        mPose = sol.pose;
      }
    }

    //! The DegenerateControl failure naming the parameter the geometry cannot determine, or nothing.
    std::optional<ResectionSummary> Resector::checkDeterminable( const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> &eigen ) const
    {
      if ( eigen.eigenvalues()( 0 ) > 1e-12 * eigen.eigenvalues().maxCoeff() )
        return std::nullopt;
      int column = 0;
      eigen.eigenvectors().col( 0 ).cwiseAbs().maxCoeff( &column );
      const char *poseNames[6] = { "X0", "Y0", "Z0", "omega", "phi", "kappa" };
      const std::vector<int> &interiorColumns = mSolution.interiorColumns;
      const std::string name = column < 6 ? poseNames[column] : column < 6 + static_cast<int>( interiorColumns.size() ) ? interiorParameterNames()[interiorColumns[column - 6]] : "a control point";
      return failure( ResectionSummary::Status::DegenerateControl, "the control geometry cannot determine " + name + " (e.g. flat control with the principal distance free); fix it or add control at other heights and positions" );
    }

    //! Sigma0, the pose (metres, degrees) and free interior with sigmas, and their correlations.
    void Resector::fillEstimates()
    {
      const Solution &sol = mSolution;
      ResectionSummary &summary = mSummary;
      summary.redundancy = static_cast<int>( sol.jacobian.rows() - sol.jacobian.cols() );
      summary.sigma0 = summary.redundancy > 0 ? std::sqrt( sol.residuals.squaredNorm() / summary.redundancy ) : 0.0;
      Eigen::MatrixXd covariance = mCofactor;
      if ( mOptions.scaleCovarianceBySigma0 && summary.redundancy > 0 )
        covariance *= summary.sigma0 * summary.sigma0;

      summary.camera = mCamera;
      cameraFromInteriorBlock( sol.interior.data(), &summary.camera );
      summary.exterior.projectionCentre = Eigen::Vector3d( sol.pose[0], sol.pose[1], sol.pose[2] ) + mOrigin;
      summary.exterior.omegaDeg = radToDeg( sol.pose[3] );
      summary.exterior.phiDeg = radToDeg( sol.pose[4] );
      summary.exterior.kappaDeg = radToDeg( sol.pose[5] );
      const int parameters = 6 + static_cast<int>( sol.interiorColumns.size() );
      const Eigen::VectorXd sigma = covariance.diagonal().head( parameters ).cwiseSqrt();
      summary.exterior.sigma = ExteriorSigma { sigma( 0 ), sigma( 1 ), sigma( 2 ), radToDeg( sigma( 3 ) ), radToDeg( sigma( 4 ) ), radToDeg( sigma( 5 ) ) };
      summary.parameterNames = { "X0", "Y0", "Z0", "omega", "phi", "kappa" };
      summary.estimates = { summary.exterior.projectionCentre.x(), summary.exterior.projectionCentre.y(), summary.exterior.projectionCentre.z(),
                            summary.exterior.omegaDeg, summary.exterior.phiDeg, summary.exterior.kappaDeg
                          };
      summary.sigmas = { sigma( 0 ), sigma( 1 ), sigma( 2 ), radToDeg( sigma( 3 ) ), radToDeg( sigma( 4 ) ), radToDeg( sigma( 5 ) ) };
      for ( size_t c = 0; c < sol.interiorColumns.size(); ++c )
      {
        summary.parameterNames.push_back( interiorParameterNames()[sol.interiorColumns[c]] );
        summary.estimates.push_back( sol.interior[sol.interiorColumns[c]] );
        summary.sigmas.push_back( sigma( 6 + c ) );
      }
      const Eigen::MatrixXd block = covariance.topLeftCorner( parameters, parameters );
      const Eigen::VectorXd inverseSigma = block.diagonal().cwiseSqrt().cwiseInverse();
      summary.correlation = inverseSigma.asDiagonal() * block * inverseSigma.asDiagonal();
    }

    //! Residuals: control (with w), then check points and removed blunders (with their error on the ground); RMSEs; the blunders named.
    void Resector::fillResiduals()
    {
      ResectionSummary &summary = mSummary;
      const OrientedImage image( summary.camera, summary.exterior );
      double sumControl = 0.0, sumCheckPx = 0.0, sumCheckM = 0.0;
      for ( size_t i = 0; i < mUsed.size(); ++i )
      {
        PointResidual r;
        r.pointId = mUsed[i].control->id;
        const Eigen::Vector3d world = Eigen::Vector3d( mUsed[i].local[0], mUsed[i].local[1], mUsed[i].local[2] ) + mOrigin;
        const GroundProjection g = image.projectGroundToPixel( world );
        r.residualPx = g.ok() ? Eigen::Vector2d( g.pixelInImage - mUsed[i].observation->pixelInImage ) : Eigen::Vector2d( mSolution.residuals.segment<2>( 2 * i ) * mUsed[i].observation->sigmaPx );
        r.normalised = mW( i );
        r.redundancy = mRedundancy( i );
        r.blunder = mW( i ) > mOptions.blunderThreshold;
        sumControl += r.residualPx.squaredNorm();
        summary.residuals.push_back( r );
      }
      for ( const UsedPoint &c : mChecks )
      {
        PointResidual r;
        r.pointId = c.control->id;
        r.check = c.control->check;
        for ( const PointResidual &b : mRemoved )
          if ( b.pointId == r.pointId )
          {
            r.blunder = true;
            r.normalised = b.normalised;
          }
        const GroundProjection g = image.projectGroundToPixel( c.control->world );
        if ( g.ok() )
          r.residualPx = g.pixelInImage - c.observation->pixelInImage;
        const PlaneIntersectionSummary ground = intersectRayWithPlane( { &image, c.observation->pixelInImage, c.observation->sigmaPx }, Plane::horizontal( c.control->world.z() ) );
        if ( ground.ok() )
          r.groundErrorM = ground.point - c.control->world;
        if ( r.check )
        {
          sumCheckPx += r.residualPx.squaredNorm();
          sumCheckM += r.groundErrorM.head<2>().squaredNorm();
          ++summary.checkCount;
        }
        summary.residuals.push_back( r );
      }
      for ( const PointResidual &b : mRemoved )
        summary.blunders.push_back( b.pointId );
      summary.controlCount = static_cast<int>( mUsed.size() );
      summary.rmseControlPx = std::sqrt( sumControl / std::max<size_t>( 1, mUsed.size() ) );
      if ( summary.checkCount > 0 )
      {
        summary.rmseCheckPx = std::sqrt( sumCheckPx / summary.checkCount );
        summary.rmseCheckM = std::sqrt( sumCheckM / summary.checkCount );
      }
      if ( !summary.blunders.empty() )
      {
        std::ostringstream m;
        m << "removed as blunder" << ( summary.blunders.size() > 1 ? "s" : "" ) << ":";
        for ( const PointResidual &b : mRemoved )
          m << " " << b.pointId << " (w = " << std::round( b.normalised * 10 ) / 10 << ")";
        summary.message = m.str();
      }
    }
  } // namespace

  const std::array<const char *, kInteriorSize> &interiorParameterNames()
  {
    static const std::array<const char *, kInteriorSize> names { "f", "cx", "cy", "k1", "k2", "p1", "p2", "k3" };
    return names;
  }

  std::optional<int> interiorParameterIndex( const std::string &name )
  {
    for ( int k = 0; k < kInteriorSize; ++k )
      if ( name == interiorParameterNames()[k] )
        return k;
    return std::nullopt;
  }


  void ResectionOptions::check() const
  {
    if ( maxIterations < 1 )
      throw std::invalid_argument( "the resection needs at least one iteration" );
    if ( robust && !( robustThreshold > 0 && std::isfinite( robustThreshold ) ) )
      throw std::invalid_argument( "the robust threshold must be a positive number of sigmas" );
    if ( !( blunderThreshold > 0 ) )
      throw std::invalid_argument( "the blunder threshold (Baarda's w) must be positive" );
    for ( const double tolerance : { functionTolerance, gradientTolerance, parameterTolerance } )
      if ( !( tolerance > 0 && tolerance < 1 ) )
        throw std::invalid_argument( "the solver's tolerances must lie between 0 and 1" );
  }

  ResectionSummary resectImage( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<ImagePoint> &observations, const ResectionOptions &options )
  {
    return Resector( camera, control, observations, options ).run();
  }

} // namespace geostation
