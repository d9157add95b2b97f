/***************************************************************************
  resection.cpp - space resection of one image from control points
 ***************************************************************************/
#include "adjustment/resection.h"

#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <ceres/ceres.h>
#include <opencv2/calib3d.hpp>

#include "adjustment/collinearityerror.h"
#include "adjustment/intersection.h"
#include "adjustment/priors.h"
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
      solverOptions.function_tolerance = 1e-14;
      solverOptions.gradient_tolerance = 1e-14;
      solverOptions.parameter_tolerance = 1e-12;
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

  ResectionSummary resectImage( const Camera &camera, const std::vector<ControlPoint> &control, const std::vector<ImagePoint> &observations, const ResectionOptions &options )
  {
    camera.validate();
    if ( camera.distortion.model == DistortionModel::None )
      for ( int k = kInteriorK1; k < kInteriorSize; ++k )
        if ( options.freeInterior[k] )
          throw std::invalid_argument( std::string( "camera '" ) + camera.id + "' has no lens model, so " + interiorParameterNames()[k] + " cannot be estimated" );

    std::map<std::string, const ImagePoint *> observed;
    for ( const ImagePoint &o : observations )
    {
      if ( !( o.sigmaPx > 0.0 ) )
        throw std::invalid_argument( "point '" + o.pointId + "': pixel sigma must be positive" );
      if ( !observed.emplace( o.pointId, &o ).second )
        throw std::invalid_argument( "point '" + o.pointId + "' is measured twice in the image" );
    }

    // Local origin: the centroid of the control, for well-conditioned numbers.
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    std::vector<UsedPoint> used, checks;
    std::set<std::string> controlIds;
    for ( const ControlPoint &c : control )
    {
      controlIds.insert( c.id );
      const auto it = observed.find( c.id );
      if ( it == observed.end() )
        continue;
      UsedPoint p { &c, it->second, {}, !c.check && ( c.sigmaM.array() > 0.0 ).all() };
      ( c.check ? checks : used ).push_back( p );
    }
    ResectionSummary summary;
    for ( const ImagePoint &o : observations )
      summary.unmatchedObservations += controlIds.count( o.pointId ) ? 0 : 1;

    int freeCount = 0;
    for ( bool f : options.freeInterior )
      freeCount += f ? 1 : 0;
    const int unknowns = 6 + freeCount;
    const int minimum = std::max( 4, unknowns / 2 + 1 );
    if ( static_cast<int>( used.size() ) < minimum )
    {
      std::ostringstream m;
      m << "a resection" << ( freeCount ? " with " + freeList( options.freeInterior ) + " free" : std::string() ) << " needs at least " << minimum
        << " control points measured in the image; " << used.size() << " given";
      return failure( ResectionSummary::Status::TooFewPoints, m.str() );
    }

    for ( const UsedPoint &p : used )
      origin += p.control->world;
    origin /= static_cast<double>( used.size() );
    const auto localise = [&origin]( UsedPoint & p )
    {
      p.knownLocal = p.control->world - origin;
      p.local = { p.knownLocal.x(), p.knownLocal.y(), p.knownLocal.z() };
    };
    std::for_each( used.begin(), used.end(), localise );
    std::for_each( checks.begin(), checks.end(), localise );

    {
      Eigen::MatrixXd centred( used.size(), 3 );
      for ( size_t i = 0; i < used.size(); ++i )
        centred.row( i ) = Eigen::Vector3d( used[i].local[0], used[i].local[1], used[i].local[2] ).transpose();
      const Eigen::Vector3d singular = Eigen::JacobiSVD<Eigen::MatrixXd>( centred ).singularValues();
      if ( !( singular( 1 ) > 1e-3 * singular( 0 ) ) )
        return failure( ResectionSummary::Status::DegenerateControl, "the control points lie (nearly) on one line, which cannot fix the image's rotation about it; add control off that line" );
    }

    std::array<double, 6> pose;
    if ( options.initial )
    {
      const Eigen::Vector3d c = options.initial->projectionCentre - origin;
      pose = { c.x(), c.y(), c.z(), degToRad( options.initial->omegaDeg ), degToRad( options.initial->phiDeg ), degToRad( options.initial->kappaDeg ) };
    }
    else
    {
      const std::optional<std::array<double, 6>> start = initialPose( camera, used );
      if ( !start || !allInFront( *start, used ) )
        return failure( ResectionSummary::Status::NoSolution, "no orientation puts the control points in front of the camera; check the point identifications and coordinates" );
      pose = *start;
    }

    // Solve; remove the worst blunder and solve again while one is found.
    std::vector<PointResidual> removed;
    Solution sol;
    Eigen::MatrixXd cofactor;
    Eigen::VectorXd w;
    for ( ;; )
    {
      sol = solve( camera, used, pose, options );
      if ( sol.solverSummary.termination_type == ceres::FAILURE || !allInFront( sol.pose, used ) )
        return failure( ResectionSummary::Status::NoSolution, "the adjustment failed: " + sol.solverSummary.message );
      // Degeneracy: the column-scaled normal matrix must be well conditioned.
      const Eigen::VectorXd scale = sol.jacobian.colwise().norm().cwiseMax( 1e-300 ).cwiseInverse();
      const Eigen::MatrixXd scaled = sol.jacobian * scale.asDiagonal();
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen( scaled.transpose() * scaled );
      if ( !( eigen.eigenvalues()( 0 ) > 1e-12 * eigen.eigenvalues().maxCoeff() ) )
      {
        int column = 0;
        eigen.eigenvectors().col( 0 ).cwiseAbs().maxCoeff( &column );
        const char *poseNames[6] = { "X0", "Y0", "Z0", "omega", "phi", "kappa" };
        const std::string name = column < 6 ? poseNames[column] : column < 6 + static_cast<int>( sol.interiorColumns.size() ) ? interiorParameterNames()[sol.interiorColumns[column - 6]] : "a control point";
        return failure( ResectionSummary::Status::DegenerateControl, "the control geometry cannot determine " + name + " (e.g. flat control with the principal distance free); fix it or add control at other heights and positions" );
      }
      const Eigen::MatrixXd normal = sol.jacobian.transpose() * sol.jacobian;
      cofactor = normal.inverse();
      const Eigen::VectorXd qvv = ( Eigen::MatrixXd::Identity( sol.jacobian.rows(), sol.jacobian.rows() ) - sol.jacobian * cofactor * sol.jacobian.transpose() ).diagonal();
      w = Eigen::VectorXd::Zero( used.size() );
      for ( size_t i = 0; i < used.size(); ++i )
        for ( int k = 0; k < 2; ++k )
          if ( qvv( 2 * i + k ) > 1e-12 )
            w( i ) = std::max( w( i ), std::abs( sol.residuals( 2 * i + k ) ) / std::sqrt( qvv( 2 * i + k ) ) );

      Eigen::Index worst = 0;
      const double worstW = used.empty() ? 0.0 : w.maxCoeff( &worst );
      if ( !( options.removeBlunders && worstW > options.blunderThreshold && static_cast<int>( used.size() ) > minimum ) )
        break;
      PointResidual blunder;
      blunder.pointId = used[worst].control->id;
      blunder.normalised = worstW;
      blunder.blunder = true;
      removed.push_back( blunder );
      checks.push_back( used[worst] ); // evaluated like a check point below
      used.erase( used.begin() + worst );
      pose = sol.pose;
    }

    summary.iterations = static_cast<int>( sol.solverSummary.iterations.size() );
    summary.converged = sol.solverSummary.termination_type == ceres::CONVERGENCE;
    if ( !summary.converged )
      return failure( ResectionSummary::Status::NotConverged, "the resection did not converge in " + std::to_string( options.maxIterations ) + " iterations: " + sol.solverSummary.message );

    summary.redundancy = static_cast<int>( sol.jacobian.rows() - sol.jacobian.cols() );
    summary.sigma0 = summary.redundancy > 0 ? std::sqrt( sol.residuals.squaredNorm() / summary.redundancy ) : 0.0;
    Eigen::MatrixXd covariance = cofactor;
    if ( options.scaleCovarianceBySigma0 && summary.redundancy > 0 )
      covariance *= summary.sigma0 * summary.sigma0;

    // Estimates and precision: pose (metres, degrees) and free interior.
    summary.camera = camera;
    cameraFromInteriorBlock( sol.interior.data(), &summary.camera );
    summary.exterior.projectionCentre = Eigen::Vector3d( sol.pose[0], sol.pose[1], sol.pose[2] ) + origin;
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

    // Residuals: control (with w), then check points and removed blunders.
    const OrientedImage image( summary.camera, summary.exterior );
    double sumControl = 0.0, sumCheckPx = 0.0, sumCheckM = 0.0;
    for ( size_t i = 0; i < used.size(); ++i )
    {
      PointResidual r;
      r.pointId = used[i].control->id;
      const Eigen::Vector3d world = Eigen::Vector3d( used[i].local[0], used[i].local[1], used[i].local[2] ) + origin;
      const GroundProjection g = image.projectGroundToPixel( world );
      r.residualPx = g.ok() ? Eigen::Vector2d( g.pixelInImage - used[i].observation->pixelInImage ) : Eigen::Vector2d( sol.residuals.segment<2>( 2 * i ) * used[i].observation->sigmaPx );
      r.normalised = w( i );
      r.blunder = w( i ) > options.blunderThreshold;
      sumControl += r.residualPx.squaredNorm();
      summary.residuals.push_back( r );
    }
    for ( const UsedPoint &c : checks )
    {
      PointResidual r;
      r.pointId = c.control->id;
      r.check = c.control->check;
      for ( const PointResidual &b : removed )
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
    for ( const PointResidual &b : removed )
      summary.blunders.push_back( b.pointId );
    summary.controlCount = static_cast<int>( used.size() );
    summary.rmseControlPx = std::sqrt( sumControl / std::max<size_t>( 1, used.size() ) );
    if ( summary.checkCount > 0 )
    {
      summary.rmseCheckPx = std::sqrt( sumCheckPx / summary.checkCount );
      summary.rmseCheckM = std::sqrt( sumCheckM / summary.checkCount );
    }
    if ( !summary.blunders.empty() )
    {
      std::ostringstream m;
      m << "removed as blunder" << ( summary.blunders.size() > 1 ? "s" : "" ) << ":";
      for ( const PointResidual &b : removed )
        m << " " << b.pointId << " (w = " << std::round( b.normalised * 10 ) / 10 << ")";
      summary.message = m.str();
    }
    return summary;
  }

} // namespace geostation
