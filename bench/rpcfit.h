// A rational polynomial (RPC) model fitted to an oriented image, so that
// GDAL's DEM-backed RPC transformer (RPC_DEM) can intersect the same pixels'
// rays with the same DEM: the baseline of the ray / DEM benchmark.
#ifndef GEOSTATION_BENCH_RPCFIT_H
#define GEOSTATION_BENCH_RPCFIT_H

#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Dense>
#include <gdal.h>

#include "geometry/crs.h"
#include "geometry/projection.h"

namespace rpcfit
{
  //! The 20 RPC00B terms of normalised (L = longitude, P = latitude, H = height).
  inline std::array<double, 20> terms( double L, double P, double H )
  {
    return { 1, L, P, H, L * P, L * H, P * H, L * L, P * P, H * H, P * L * H, L * L * L, L * P * P, L * H * H, L * L * P, P * P * P, P * H * H, L * L * H, P * P * H, H * H * H };
  }

  /**
   * Fits an RPC to `image` from ground points (block CRS) along its rays,
   * `toWgs84` mapping the block CRS to longitude/latitude. GDAL's RPC
   * convention puts (0, 0) at the centre of the first pixel, hence - 0.5.
   */
  inline GDALRPCInfoV2 fit( const geostation::OrientedImage &image, const std::vector<Eigen::Vector3d> &ground, const geostation::CrsTransform &toWgs84 )
  {
    std::vector<Eigen::Vector3d> llh;
    std::vector<Eigen::Vector2d> pixels;
    for ( const Eigen::Vector3d &p : ground )
    {
      const geostation::GroundProjection g = image.projectGroundToPixel( p );
      if ( !g.ok() )
        continue;
      const Eigen::Vector3d q = toWgs84.transform( p );
      llh.emplace_back( q.x(), q.y(), p.z() );
      pixels.push_back( g.pixelInImage - Eigen::Vector2d( 0.5, 0.5 ) );
    }
    GDALRPCInfoV2 rpc {};
    Eigen::Vector3d lo = llh.front(), hi = llh.front();
    Eigen::Vector2d plo = pixels.front(), phi = pixels.front();
    for ( size_t i = 0; i < llh.size(); ++i )
    {
      lo = lo.cwiseMin( llh[i] );
      hi = hi.cwiseMax( llh[i] );
      plo = plo.cwiseMin( pixels[i] );
      phi = phi.cwiseMax( pixels[i] );
    }
    rpc.dfLONG_OFF = 0.5 * ( lo.x() + hi.x() );
    rpc.dfLAT_OFF = 0.5 * ( lo.y() + hi.y() );
    rpc.dfHEIGHT_OFF = 0.5 * ( lo.z() + hi.z() );
    rpc.dfLONG_SCALE = 0.5 * ( hi.x() - lo.x() );
    rpc.dfLAT_SCALE = 0.5 * ( hi.y() - lo.y() );
    rpc.dfHEIGHT_SCALE = std::max( 1.0, 0.5 * ( hi.z() - lo.z() ) );
    rpc.dfSAMP_OFF = 0.5 * ( plo.x() + phi.x() );
    rpc.dfLINE_OFF = 0.5 * ( plo.y() + phi.y() );
    rpc.dfSAMP_SCALE = 0.5 * ( phi.x() - plo.x() );
    rpc.dfLINE_SCALE = 0.5 * ( phi.y() - plo.y() );
    rpc.dfMIN_LONG = lo.x();
    rpc.dfMAX_LONG = hi.x();
    rpc.dfMIN_LAT = lo.y();
    rpc.dfMAX_LAT = hi.y();
    const int n = static_cast<int>( llh.size() );
    for ( int axis = 0; axis < 2; ++axis )
    {
      // value * (1 + den[1..19] . t[1..19]) = num . t  ->  num . t - value * den . t = value
      Eigen::MatrixXd A( n, 39 );
      Eigen::VectorXd b( n );
      for ( int i = 0; i < n; ++i )
      {
        const std::array<double, 20> t = terms( ( llh[i].x() - rpc.dfLONG_OFF ) / rpc.dfLONG_SCALE, ( llh[i].y() - rpc.dfLAT_OFF ) / rpc.dfLAT_SCALE,
                                                ( llh[i].z() - rpc.dfHEIGHT_OFF ) / rpc.dfHEIGHT_SCALE );
        const double v = axis == 0 ? ( pixels[i].x() - rpc.dfSAMP_OFF ) / rpc.dfSAMP_SCALE : ( pixels[i].y() - rpc.dfLINE_OFF ) / rpc.dfLINE_SCALE;
        for ( int k = 0; k < 20; ++k )
          A( i, k ) = t[k];
        for ( int k = 1; k < 20; ++k )
          A( i, 19 + k ) = -v * t[k];
        b( i ) = v;
      }
      const Eigen::VectorXd x = A.colPivHouseholderQr().solve( b );
      double *num = axis == 0 ? rpc.adfSAMP_NUM_COEFF : rpc.adfLINE_NUM_COEFF;
      double *den = axis == 0 ? rpc.adfSAMP_DEN_COEFF : rpc.adfLINE_DEN_COEFF;
      den[0] = 1.0;
      for ( int k = 0; k < 20; ++k )
        num[k] = x( k );
      for ( int k = 1; k < 20; ++k )
        den[k] = x( 19 + k );
    }
    return rpc;
  }
}

#endif
