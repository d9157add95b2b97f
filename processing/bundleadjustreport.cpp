/***************************************************************************
  bundleadjustreport.cpp - the REPORT of geostation:bundle_adjust
 ***************************************************************************/
#include "bundleadjustreport.h"

#include <QJsonArray>

namespace GeoStationProcessing
{
  namespace
  {
    QJsonObject xyz( const Eigen::Vector3d &v )
    {
      return QJsonObject { { "x", v.x() }, { "y", v.y() }, { "z", v.z() } };
    }
  } // namespace

  QString bundlePointRoleName( geostation::BundlePointResult::Role role )
  {
    switch ( role )
    {
      case geostation::BundlePointResult::Role::Control:
        return QStringLiteral( "control" );
      case geostation::BundlePointResult::Role::Check:
        return QStringLiteral( "check" );
      case geostation::BundlePointResult::Role::Tie:
        break;
    }
    return QStringLiteral( "tie" );
  }


  QJsonObject bundleAdjustReport( const geostation::BundleSummary &s )
  {
    QJsonObject report;
    report.insert( "algorithm", "geostation:bundle_adjust" );
    report.insert( "sigma0_px", s.sigma0 );
    report.insert( "redundancy", static_cast<double>( s.redundancy ) );
    report.insert( "iterations", s.iterations );
    report.insert( "converged", s.converged );
    report.insert( "solve_seconds", s.solveSeconds );
    report.insert( "rms_px", s.rmsPx );
    QJsonArray images;
    for ( const geostation::BundleImageResult &i : s.images )
    {
      if ( i.observationCount == 0 )
        continue;
      const geostation::ExteriorOrientation &eo = i.exterior;
      QJsonObject o { { "image_id", QString::fromStdString( i.id ) }, { "observations", i.observationCount }, { "rms_px", i.rmsPx },
        { "X", eo.projectionCentre.x() }, { "Y", eo.projectionCentre.y() }, { "Z", eo.projectionCentre.z() },
        { "omega", eo.omegaDeg }, { "phi", eo.phiDeg }, { "kappa", eo.kappaDeg }, { "shift_m", xyz( i.shiftM ) } };
      if ( eo.sigma )
        o.insert( "sigma", QJsonObject { { "X", eo.sigma->x }, { "Y", eo.sigma->y }, { "Z", eo.sigma->z },
          { "omega", eo.sigma->omegaDeg }, { "phi", eo.sigma->phiDeg }, { "kappa", eo.sigma->kappaDeg } } );
      images.append( o );
    }
    report.insert( "images", images );
    QJsonArray cameras;
    for ( const geostation::BundleCameraResult &c : s.cameras )
    {
      if ( c.freeParameters.empty() )
        continue;
      QJsonArray parameters;
      double values[geostation::kInteriorSize];
      geostation::interiorBlockFromCamera( c.camera, values );
      for ( size_t k = 0; k < c.freeParameters.size(); ++k )
        parameters.append( QJsonObject { { "name", QString::fromStdString( c.freeParameters[k] ) },
          { "value", values[*geostation::interiorParameterIndex( c.freeParameters[k] )] }, { "sigma", c.sigmas[k] } } );
      cameras.append( QJsonObject { { "camera_id", QString::fromStdString( c.camera.id ) }, { "parameters", parameters } } );
    }
    report.insert( "cameras", cameras );
    QJsonArray points;
    for ( const geostation::BundlePointResult &p : s.points )
    {
      if ( p.role == geostation::BundlePointResult::Role::Tie )
        continue;
      points.append( QJsonObject { { "point_id", QString::fromStdString( p.id ) }, { "role", bundlePointRoleName( p.role ) }, { "n_images", p.imageCount },
        { "rms_px", p.rmsPx }, { "error_m", xyz( p.errorM ) }, { "sigma_m", xyz( p.sigmaM ) } } );
    }
    report.insert( "ground_points", points );
    QJsonArray residuals;
    for ( const geostation::BundleObservationResult &o : s.observations )
      residuals.append( QJsonObject { { "point_id", QString::fromStdString( o.pointId ) }, { "image_id", QString::fromStdString( o.imageId ) }, { "col", o.pixelInImage.x() },
        { "row", o.pixelInImage.y() }, { "col_resid_px", o.residualPx.x() }, { "row_resid_px", o.residualPx.y() } } );
    report.insert( "residuals", residuals );
    report.insert( "rmse_control_m", s.controlCount ? QJsonValue( xyz( s.rmseControlM ) ) : QJsonValue() );
    QJsonObject check = xyz( s.rmseCheckM );
    check.insert( "planimetric", s.rmseCheckM.head<2>().norm() );
    check.insert( "total", s.rmseCheckM.norm() );
    report.insert( "rmse_check_m", s.checkCount ? QJsonValue( check ) : QJsonValue() );
    report.insert( "control_count", s.controlCount );
    report.insert( "check_count", s.checkCount );
    QJsonArray skipped;
    for ( const std::string &id : s.skippedPoints )
      skipped.append( QString::fromStdString( id ) );
    report.insert( "skipped_points", skipped );
    return report;
  }
}
