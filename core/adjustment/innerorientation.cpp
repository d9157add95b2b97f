/***************************************************************************
  innerorientation.cpp - inner orientation of a scanned photo from fiducials
 ***************************************************************************/
#include "adjustment/innerorientation.h"

#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <Eigen/Dense>

#include "geometry/rotation.h"

namespace geostation
{

  AffineDecomposition decomposeAffine( const Eigen::Matrix2d &a )
  {
    // a = [[p + r, t - q], [t + q, p - r]]: a similarity (p, q) plus an
    // anti-similarity (r, t); A, B = |sim| +- |anti|.
    const double a11 = a( 0, 0 ), a12 = a( 0, 1 ), a21 = a( 1, 0 ), a22 = a( 1, 1 );
    const double similarity = std::hypot( a11 + a22, a21 - a12 );
    const double anti = std::hypot( a11 - a22, a21 + a12 );
    AffineDecomposition d;
    d.scaleA = 0.5 * ( similarity + anti );
    d.scaleB = 0.5 * ( similarity - anti );
    d.affinityPct = d.scaleB > 0.0 ? 100.0 * ( d.scaleA / d.scaleB - 1.0 ) : 0.0;
    // beta = arctan[(a12 - a21) / (a11 + a22)], alpha_A = (beta + arctan[(a12 + a21) / (a11 - a22)]) / 2,
    // taken with atan2 so every quadrant is right.
    const double beta = std::atan2( a12 - a21, a11 + a22 );
    double alpha = 0.5 * ( beta + std::atan2( a12 + a21, a11 - a22 ) );
    // Directions are axial: report alpha_A in (-90, 90].
    while ( alpha > kPi / 2 )
      alpha -= kPi;
    while ( alpha <= -kPi / 2 )
      alpha += kPi;
    d.betaDeg = radToDeg( beta );
    d.alphaADeg = radToDeg( alpha );
    d.alphaBDeg = d.alphaADeg + 90.0;
    return d;
  }

  InnerOrientationSummary innerOrientation( const std::vector<Fiducial> &calibrated, const std::vector<FiducialMeasurement> &measured )
  {
    std::map<std::string, Eigen::Vector2d> known;
    for ( const Fiducial &f : calibrated )
      known[f.id] = f.photoMm;
    std::set<std::string> seen;
    std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> pairs; // (u, v) and photo mm
    std::vector<std::string> ids;
    for ( const FiducialMeasurement &m : measured )
    {
      const auto it = known.find( m.id );
      if ( it == known.end() )
        throw std::invalid_argument( "fiducial '" + m.id + "' is measured but the camera does not define it" );
      if ( !seen.insert( m.id ).second )
        throw std::invalid_argument( "fiducial '" + m.id + "' is measured twice" );
      pairs.emplace_back( Eigen::Vector2d( m.pixelInImage.x(), -m.pixelInImage.y() ), it->second );
      ids.push_back( m.id );
    }

    InnerOrientationSummary s;
    const int n = static_cast<int>( pairs.size() );
    if ( n < 3 )
    {
      s.status = InnerOrientationSummary::Status::TooFewFiducials;
      s.message = "an affine inner orientation needs at least three measured fiducials; " + std::to_string( n ) + " given";
      return s;
    }
    Eigen::Vector2d uv0 = Eigen::Vector2d::Zero(), xy0 = Eigen::Vector2d::Zero();
    for ( const auto &[uv, xy] : pairs )
    {
      uv0 += uv;
      xy0 += xy;
    }
    uv0 /= n;
    xy0 /= n;
    Eigen::MatrixXd U( n, 2 ), X( n, 2 );
    for ( int i = 0; i < n; ++i )
    {
      U.row( i ) = ( pairs[i].first - uv0 ).transpose();
      X.row( i ) = ( pairs[i].second - xy0 ).transpose();
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd( U, Eigen::ComputeThinU | Eigen::ComputeThinV );
    if ( !( svd.singularValues()( 1 ) > 1e-6 * svd.singularValues()( 0 ) ) )
    {
      s.status = InnerOrientationSummary::Status::Degenerate;
      s.message = "the measured fiducials lie (nearly) on one line; measure fiducials in at least three corners";
      return s;
    }
    // X = U a^T  ->  a^T = U^+ X
    s.a = svd.solve( X ).transpose();
    if ( !( s.a.determinant() > 0.0 ) )
    {
      s.status = InnerOrientationSummary::Status::Degenerate;
      s.message = "the fiducials' order is mirrored (negative determinant): check the fiducial ids or whether the scan is flipped";
      return s;
    }
    s.fiducialCentreMm = xy0;
    s.fiducialCentrePx = Eigen::Vector2d( uv0.x(), -uv0.y() );
    s.decomposition = decomposeAffine( s.a );
    // photo = xy0 + a * ((col, -row) - uv0) = a * diag(1, -1) * (col, row) + (xy0 - a uv0)
    s.photoFromPixel.leftCols<2>() = s.a * Eigen::DiagonalMatrix<double, 2>( 1.0, -1.0 );
    s.photoFromPixel.col( 2 ) = xy0 - s.a * uv0;

    double sumSquares = 0.0;
    for ( int i = 0; i < n; ++i )
    {
      const Eigen::Vector2d residual = xy0 + s.a * ( pairs[i].first - uv0 ) - pairs[i].second;
      s.residuals.push_back( { ids[i], residual } );
      sumSquares += residual.squaredNorm();
    }
    s.redundancy = 2 * n - 6;
    s.sigma0Mm = s.redundancy > 0 ? std::sqrt( sumSquares / s.redundancy ) : 0.0;
    s.rmsResidualMm = std::sqrt( sumSquares / n );
    return s;
  }

} // namespace geostation
