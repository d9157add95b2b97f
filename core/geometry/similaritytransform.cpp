/***************************************************************************
  similaritytransform.cpp - seven-parameter similarity (Helmert) transform
 ***************************************************************************/
#include "geometry/similaritytransform.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "geometry/rotation.h"

namespace geostation
{

  ExteriorOrientation SimilarityTransform::apply( const ExteriorOrientation &exteriorInSource ) const
  {
    return ExteriorOrientation::fromCentreAndRotation( apply( exteriorInSource.projectionCentre ), rotation * exteriorInSource.worldFromCamera() );
  }

  SimilarityTransform SimilarityTransform::inverse() const
  {
    SimilarityTransform inv;
    inv.scale = 1.0 / scale;
    inv.rotation = rotation.transpose();
    inv.translation = -inv.scale * ( inv.rotation * translation );
    return inv;
  }

  SimilarityFitSummary fitSimilarityTransform( const std::vector<Eigen::Vector3d> &source, const std::vector<Eigen::Vector3d> &target,
      const std::vector<std::string> &names )
  {
    const size_t n = source.size();
    if ( target.size() != n || ( !names.empty() && names.size() != n ) )
      throw std::invalid_argument( "the similarity transform needs as many target points as source points" );
    if ( n < 3 )
      throw std::invalid_argument( "a similarity transform needs at least three known points; " + std::to_string( n ) + " given" );
    for ( size_t i = 0; i < n; ++i )
      if ( !source[i].allFinite() || !target[i].allFinite() )
        throw std::invalid_argument( "point " + ( names.empty() ? std::to_string( i + 1 ) : "\"" + names[i] + "\"" ) + " of the similarity transform has a coordinate that is not a number" );

    // centred in both frames, so that projected coordinates (10^6 m) lose no digits
    Eigen::Vector3d sourceMean = Eigen::Vector3d::Zero(), targetMean = Eigen::Vector3d::Zero();
    for ( size_t i = 0; i < n; ++i )
    {
      sourceMean += source[i];
      targetMean += target[i];
    }
    sourceMean /= double( n );
    targetMean /= double( n );
    Eigen::Matrix3Xd src( 3, n ), dst( 3, n );
    for ( size_t i = 0; i < n; ++i )
    {
      src.col( i ) = source[i] - sourceMean;
      dst.col( i ) = target[i] - targetMean;
    }

    // collinear (or coincident) points leave the rotation about their line free
    double spreadRatio = 1.0;
    for ( const Eigen::Matrix3Xd *points : { &src, &dst } )
    {
      const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd( *points );
      const Eigen::Vector3d sv = svd.singularValues();
      if ( !( sv[0] > 0.0 ) || sv[1] < 1e-6 * sv[0] )
        throw std::invalid_argument( "the known points of the similarity transform are " + std::string( sv[0] > 0.0 ? "on one line" : "all at one place" )
                                     + " (in the " + ( points == &src ? "model" : "target" ) + "), so the rotation about that line is undetermined; give points that span a plane" );
      spreadRatio = std::min( spreadRatio, sv[1] / sv[0] );
    }

    const Eigen::Matrix4d m = Eigen::umeyama( src, dst, true );
    SimilarityFitSummary summary;
    SimilarityTransform &t = summary.targetFromSource;
    const Eigen::Matrix3d sR = m.topLeftCorner<3, 3>();
    t.scale = std::cbrt( sR.determinant() );
    t.rotation = sR / t.scale;
    // translation for uncentred coordinates: target = sR (source - sMean) + tc + tMean
    t.translation = m.topRightCorner<3, 1>() + targetMean - sR * sourceMean;

    double sum2 = 0.0;
    for ( size_t i = 0; i < n; ++i )
    {
      SimilarityPairResidual r;
      r.name = names.empty() ? std::to_string( i + 1 ) : names[i];
      r.target = target[i];
      // residual from the centred form: exact for large coordinates
      r.residualM = dst.col( i ) - ( sR * src.col( i ) + m.topRightCorner<3, 1>() );
      sum2 += r.residualM.squaredNorm();
      summary.maxM = std::max( summary.maxM, r.residualM.norm() );
      summary.residuals.push_back( r );
    }
    summary.spreadRatio = spreadRatio;
    summary.rmsM = std::sqrt( sum2 / double( n ) );
    summary.sigma0M = std::sqrt( sum2 / double( 3 * n - 7 ) );
    return summary;
  }

} // namespace geostation
