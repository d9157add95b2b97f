/***************************************************************************
  pairmapping.cpp - from one image of a stereo pair to the other
 ***************************************************************************/
#include "extraction/pairmapping.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

namespace geostation
{

  namespace
  {
    //! Throws unless the points span a plane (their scatter is not a line).
    void requireNotCollinear( const std::vector<Eigen::Vector2d> &points, const std::string &what )
    {
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for ( const Eigen::Vector2d &p : points )
        mean += p / static_cast<double>( points.size() );
      Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
      for ( const Eigen::Vector2d &p : points )
        scatter += ( p - mean ) * ( p - mean ).transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig( scatter );
      const double small = std::sqrt( std::max( 0.0, eig.eigenvalues()( 0 ) ) ), large = std::sqrt( std::max( 0.0, eig.eigenvalues()( 1 ) ) );
      if ( !( large > 0.0 ) || small < 1e-3 * large )
        throw std::invalid_argument( "the control points of the " + what + " mapping lie on a line: it needs points spread over the overlap" );
    }

    //! The pairs' points in A and in B, checked: numbers, and spread over a plane in both images.
    void splitPairs( const std::vector<ControlPair> &pairs, const std::string &mapping, std::vector<Eigen::Vector2d> &a, std::vector<Eigen::Vector2d> &b )
    {
      for ( const ControlPair &p : pairs )
      {
        if ( !p.inA.allFinite() || !p.inB.allFinite() )
          throw std::invalid_argument( "control point \"" + p.id + "\" has a coordinate that is not a number" );
        a.push_back( p.inA );
        b.push_back( p.inB );
      }
      requireNotCollinear( a, mapping );
      requireNotCollinear( b, mapping );
    }

    Eigen::Matrix3d normalising( const std::vector<Eigen::Vector2d> &points )
    {
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for ( const Eigen::Vector2d &p : points )
        mean += p / static_cast<double>( points.size() );
      double spread = 0.0;
      for ( const Eigen::Vector2d &p : points )
        spread += ( p - mean ).norm() / points.size();
      const double s = spread > 0 ? std::sqrt( 2.0 ) / spread : 1.0;
      Eigen::Matrix3d t;
      t << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
      return t;
    }

    //! The homography `to` = H `from` by the normalised DLT (least squares beyond four points).
    Eigen::Matrix3d homography( const std::vector<Eigen::Vector2d> &from, const std::vector<Eigen::Vector2d> &to )
    {
      const Eigen::Matrix3d tf = normalising( from ), tt = normalising( to );
      Eigen::MatrixXd a( 2 * from.size(), 9 );
      for ( size_t i = 0; i < from.size(); ++i )
      {
        const Eigen::Vector3d p = tf * from[i].homogeneous(), q = tt * to[i].homogeneous();
        a.row( 2 * i ) << 0, 0, 0, -q.z() * p.transpose(), q.y() * p.transpose();
        a.row( 2 * i + 1 ) << q.z() * p.transpose(), 0, 0, 0, -q.x() * p.transpose();
      }
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd( a, Eigen::ComputeFullV );
      const Eigen::VectorXd h = svd.matrixV().col( 8 );
      Eigen::Matrix3d hn;
      hn << h( 0 ), h( 1 ), h( 2 ), h( 3 ), h( 4 ), h( 5 ), h( 6 ), h( 7 ), h( 8 );
      return tt.inverse() * hn * tf;
    }

    std::optional<Eigen::Vector2d> applyHomography( const Eigen::Matrix3d &h, const Eigen::Vector2d &p )
    {
      const Eigen::Vector3d q = h * p.homogeneous();
      if ( std::abs( q.z() ) < 1e-12 )
        return std::nullopt;
      return Eigen::Vector2d( q.x() / q.z(), q.y() / q.z() );
    }

    void fillReport( RegistrationReport *report, const std::string &method, const std::vector<double> &residuals )
    {
      if ( !report )
        return;
      report->method = method;
      report->residualsPx = residuals;
      double sum = 0.0, worst = 0.0;
      for ( double r : residuals )
      {
        sum += r * r;
        worst = std::max( worst, r );
      }
      report->rmsPx = residuals.empty() ? 0.0 : std::sqrt( sum / residuals.size() );
      report->maxPx = worst;
    }

    MultiquadricMapping::Surface fitSurface( const std::vector<Eigen::Vector2d> &from, const std::vector<Eigen::Vector2d> &to, double smoothing )
    {
      MultiquadricMapping::Surface s;
      s.nodes = from;
      s.shift = to.front() - from.front(); // eqs. 4-9, 4-10 from the first pair
      double minD2 = std::numeric_limits<double>::infinity();
      for ( size_t i = 0; i < from.size(); ++i )
        for ( size_t k = i + 1; k < from.size(); ++k )
          minD2 = std::min( minD2, ( from[i] - from[k] ).squaredNorm() );
      if ( !( minD2 > 1e-6 ) )
        throw std::invalid_argument( "two control points of the multiquadric mapping are at the same place" );
      s.sf = smoothing * minD2;
      const int n = static_cast<int>( from.size() );
      Eigen::MatrixXd phi( n, n );
      Eigen::MatrixX2d rhs( n, 2 );
      for ( int i = 0; i < n; ++i )
      {
        for ( int k = 0; k < n; ++k )
          phi( i, k ) = std::sqrt( ( from[i] - from[k] ).squaredNorm() + s.sf );
        rhs.row( i ) = ( to[i] - from[i] - s.shift ).transpose();
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu( phi );
      if ( lu.rank() < n )
        throw std::invalid_argument( "the multiquadric mapping's equations are singular for these control points" );
      s.coefficients = lu.solve( rhs );
      return s;
    }
  } // namespace

  ProjectiveMapping ProjectiveMapping::fit( const std::vector<ControlPair> &pairs, RegistrationReport *report )
  {
    if ( pairs.size() < 4 )
      throw std::invalid_argument( "the projective mapping needs at least 4 control-point pairs, got " + std::to_string( pairs.size() ) );
    std::vector<Eigen::Vector2d> a, b;
    splitPairs( pairs, "projective", a, b );
    ProjectiveMapping m;
    m.mBFromA = homography( a, b );
    m.mAFromB = m.mBFromA.inverse();
    std::vector<double> residuals;
    for ( const ControlPair &p : pairs )
    {
      const std::optional<Eigen::Vector2d> q = m.toB( p.inA );
      residuals.push_back( q ? ( *q - p.inB ).norm() : std::numeric_limits<double>::infinity() );
    }
    fillReport( report, "projective", residuals );
    if ( report && pairs.size() > 4 )
    {
      const double equations = 2.0 * pairs.size();
      report->expectedPx = report->maxPx * std::sqrt( equations / ( equations - 8.0 ) );
    }
    return m;
  }

  std::optional<Eigen::Vector2d> ProjectiveMapping::toB( const Eigen::Vector2d &pixelInA ) const { return applyHomography( mBFromA, pixelInA ); }
  std::optional<Eigen::Vector2d> ProjectiveMapping::toA( const Eigen::Vector2d &pixelInB ) const { return applyHomography( mAFromB, pixelInB ); }

  Eigen::Vector2d MultiquadricMapping::Surface::apply( const Eigen::Vector2d &p ) const
  {
    Eigen::Vector2d out = p + shift;
    for ( size_t k = 0; k < nodes.size(); ++k )
      out += std::sqrt( ( p - nodes[k] ).squaredNorm() + sf ) * coefficients.row( static_cast<Eigen::Index>( k ) ).transpose();
    return out;
  }

  MultiquadricMapping MultiquadricMapping::fit( const std::vector<ControlPair> &pairs, double smoothing, RegistrationReport *report )
  {
    if ( pairs.size() < 3 )
      throw std::invalid_argument( "the multiquadric mapping needs at least 3 control-point pairs, got " + std::to_string( pairs.size() ) );
    if ( !( smoothing >= 0.0 ) )
      throw std::invalid_argument( "the multiquadric smoothing factor must not be negative" );
    std::vector<Eigen::Vector2d> a, b;
    splitPairs( pairs, "multiquadric", a, b );
    MultiquadricMapping m;
    m.mForward = fitSurface( a, b, smoothing );
    m.mBackward = fitSurface( b, a, smoothing );
    // it passes through its points: the misregistration is judged leaving each point out
    std::vector<double> residuals;
    for ( size_t i = 0; i < pairs.size(); ++i )
    {
      if ( pairs.size() < 4 )
      {
        residuals.push_back( std::numeric_limits<double>::quiet_NaN() );
        continue;
      }
      std::vector<Eigen::Vector2d> ra, rb;
      for ( size_t k = 0; k < pairs.size(); ++k )
        if ( k != i )
        {
          ra.push_back( a[k] );
          rb.push_back( b[k] );
        }
      try
      {
        residuals.push_back( ( fitSurface( ra, rb, smoothing ).apply( a[i] ) - b[i] ).norm() );
      }
      catch ( const std::invalid_argument & )
      {
        residuals.push_back( std::numeric_limits<double>::quiet_NaN() );
      }
    }
    fillReport( report, "multiquadric", residuals );
    if ( report && pairs.size() >= 4 )
    {
      double worst = 0.0;
      int judged = 0;
      for ( double r : residuals )
        if ( std::isfinite( r ) )
        {
          worst = std::max( worst, r );
          ++judged;
        }
      if ( judged >= 3 )
        report->expectedPx = worst;
    }
    return m;
  }

  std::optional<Eigen::Vector2d> MultiquadricMapping::toB( const Eigen::Vector2d &pixelInA ) const { return mForward.apply( pixelInA ); }
  std::optional<Eigen::Vector2d> MultiquadricMapping::toA( const Eigen::Vector2d &pixelInB ) const { return mBackward.apply( pixelInB ); }

  OrientedPairMapping::OrientedPairMapping( const OrientedImage &a, const OrientedImage &b, double meanHeightM, TerrainHeight terrain )
    : mA( a ), mB( b ), mMeanHeightM( meanHeightM ), mTerrain( std::move( terrain ) )
  {
    if ( !std::isfinite( meanHeightM ) )
      throw std::invalid_argument( "the mean terrain height must be a number" );
  }

  std::optional<Eigen::Vector3d> OrientedPairMapping::groundPoint( const OrientedImage &image, const Eigen::Vector2d &pixelInImage ) const
  {
    const std::optional<Ray> ray = image.worldRayFromPixel( pixelInImage );
    if ( !ray || std::abs( ray->direction.z() ) < 1e-6 )
      return std::nullopt;
    double z = mMeanHeightM;
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for ( int iteration = 0; iteration < 30; ++iteration )
    {
      const double t = ( z - ray->origin.z() ) / ray->direction.z();
      if ( t <= 0.0 )
        return std::nullopt;
      p = ray->origin + t * ray->direction;
      const std::optional<double> h = mTerrain ? mTerrain( p.x(), p.y() ) : std::nullopt;
      const double next = h ? *h : mMeanHeightM;
      if ( std::abs( next - z ) < 0.01 )
        break;
      z = 0.5 * ( z + next ); // damped: converges on slopes steeper than the ray
    }
    return p;
  }

  std::optional<Eigen::Vector2d> OrientedPairMapping::toB( const Eigen::Vector2d &pixelInA ) const
  {
    const std::optional<Eigen::Vector3d> ground = groundPoint( mA, pixelInA );
    if ( !ground )
      return std::nullopt;
    const GroundProjection g = mB.projectGroundToPixel( *ground );
    return g.ok() ? std::optional<Eigen::Vector2d>( g.pixelInImage ) : std::nullopt;
  }

  std::optional<Eigen::Vector2d> OrientedPairMapping::toA( const Eigen::Vector2d &pixelInB ) const
  {
    const std::optional<Eigen::Vector3d> ground = groundPoint( mB, pixelInB );
    if ( !ground )
      return std::nullopt;
    const GroundProjection g = mA.projectGroundToPixel( *ground );
    return g.ok() ? std::optional<Eigen::Vector2d>( g.pixelInImage ) : std::nullopt;
  }

} // namespace geostation
