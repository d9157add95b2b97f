/***************************************************************************
  intersectalgorithm.cpp - geostation:intersect
 ***************************************************************************/
#include "intersectalgorithm.h"

#include <map>
#include <memory>

#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsgeometry.h>
#include <qgspoint.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>

#include "adjustment/intersection.h"
#include "processingblock.h"
#include "processingtables.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

QString IntersectAlgorithm::name() const
{
  return QStringLiteral( "intersect" );
}

QString IntersectAlgorithm::displayName() const
{
  return QObject::tr( "Intersect image points (multi-ray)" );
}

QStringList IntersectAlgorithm::tags() const
{
  return QObject::tr( "photogrammetry,intersection,triangulation,stereo,multi-ray,3d,precision" ).split( ',' );
}

QString IntersectAlgorithm::group() const
{
  return QObject::tr( "Adjustment" );
}

QString IntersectAlgorithm::groupId() const
{
  return QStringLiteral( "adjustment" );
}

QString IntersectAlgorithm::helpText() const
{
  return QObject::tr( "Computes the 3D position of every point measured in two or more oriented images of a block, "
                      "by least squares on the collinearity equations with the cameras' lens distortion.\n\n"
                      "OBSERVATIONS is a table with point_id, image_id, col, row (pixels) and optionally sigma_px "
                      "(otherwise SIGMA_PX applies). Its other fields are carried to the output from each point's first row.\n\n"
                      "The output (PointZ, block CRS) has point_id, n_images, sigma_x, sigma_y, sigma_z (metres, from the "
                      "pixel sigmas), rms_px and max_resid_px (image residuals), ray_angle_deg (the largest angle between two "
                      "rays: small angles mean weak depth), sigma0, gross_error (a normalised residual above 4) and suspect_image "
                      "(the image most likely wrong, when three or more rays allow telling), and status: ok, or why the point "
                      "cannot be intersected - too_few_rays (seen in one image), parallel_rays, behind_camera, ray_undefined, "
                      "no_solution - with the sentence in message; such a point is kept without geometry, with a warning. "
                      "The run fails only when no point can be intersected." );
}

IntersectAlgorithm *IntersectAlgorithm::createInstance() const
{
  return new IntersectAlgorithm();
}

void IntersectAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "OBSERVATIONS" ), QObject::tr( "Image observations (point_id, image_id, col, row)" ),
                QList<int>() << QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "SIGMA_PX" ), QObject::tr( "Pixel sigma where the table has none" ),
                QgsProcessingParameterNumber::Double, 0.5, false, 1e-6 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Intersected points" ), QgsProcessing::TypeVectorPoint ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "POINT_COUNT" ), QObject::tr( "Points intersected" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "SKIPPED_COUNT" ), QObject::tr( "Points skipped" ) ) );
}

QVariantMap IntersectAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QgsCoordinateReferenceSystem crs = GeoStationProcessing::blockCrs( block );
  std::unique_ptr<QgsProcessingFeatureSource> source( parameterAsSource( parameters, QStringLiteral( "OBSERVATIONS" ), context ) );
  if ( !source )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "OBSERVATIONS" ) ) );
  const double defaultSigma = parameterAsDouble( parameters, QStringLiteral( "SIGMA_PX" ), context );
  const GeoStationProcessing::ObservationTable table = GeoStationProcessing::readObservations( source.get(), QObject::tr( "observations" ), feedback );

  // Every image named must exist and be oriented: checked before anything is written.
  std::map<QString, std::unique_ptr<geostation::OrientedImage>> images;
  for ( const GeoStationProcessing::ObservationRecord &r : table.rows )
    if ( !images.count( r.imageId ) )
    {
      const geostation::BlockImage &image = GeoStationProcessing::blockImage( block, r.imageId );
      images[r.imageId] = std::make_unique<geostation::OrientedImage>( GeoStationProcessing::orientedImage( block, image ) );
    }

  // Group by point, in order of first appearance.
  QStringList order;
  QMap<QString, QVector<int>> rowsOfPoint;
  for ( int i = 0; i < table.rows.size(); ++i )
  {
    if ( !rowsOfPoint.contains( table.rows[i].pointId ) )
      order << table.rows[i].pointId;
    rowsOfPoint[table.rows[i].pointId] << i;
  }

  QgsFields fields;
  fields.append( QgsField( QLatin1String( fs::kPointId ), QVariant::String ) );
  fields.append( QgsField( QStringLiteral( "n_images" ), QVariant::Int ) );
  for ( const char *name : { "sigma_x", "sigma_y", "sigma_z", "rms_px", "max_resid_px", "ray_angle_deg", "sigma0" } )
    fields.append( QgsField( QString::fromLatin1( name ), QVariant::Double ) );
  fields.append( QgsField( QStringLiteral( "gross_error" ), QVariant::Bool ) );
  fields.append( QgsField( QStringLiteral( "suspect_image" ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kStatus ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kMessage ), QVariant::String ) );
  // The observation table's other fields, except those whose names the output already uses.
  QVector<int> carried;
  for ( int e = 0; e < table.extraFields.count(); ++e )
    if ( fields.indexFromName( table.extraFields.at( e ).name() ) < 0 )
    {
      fields.append( table.extraFields.at( e ) );
      carried << e;
    }

  QVector<QgsFeature> features;
  QStringList skipped;
  long intersected = 0;
  StatusTally statusCounts;
  for ( int k = 0; k < order.size(); ++k )
  {
    if ( feedback->isCanceled() )
      return QVariantMap();
    const QString &pointId = order[k];
    const QVector<int> &rows = rowsOfPoint[pointId];
    std::vector<geostation::RayObservation> observations;
    for ( int i : rows )
    {
      const GeoStationProcessing::ObservationRecord &r = table.rows[i];
      observations.push_back( { images[r.imageId].get(), r.pixel, r.sigmaPx > 0.0 ? r.sigmaPx : defaultSigma } );
    }
    const geostation::IntersectionSummary s = geostation::intersectRays( observations );
    const QString status = QString::fromStdString( geostation::intersectionStatusName( s.status ) );
    statusCounts.add( status );
    QgsFeature f( fields );
    QgsAttributes attributes;
    const QVariant none;
    if ( !s.ok() )
    {
      // kept with an empty geometry and why (one point that cannot be intersected does not stop the others)
      skipped << QStringLiteral( "%1 (%2)" ).arg( pointId, QString::fromStdString( s.message ) );
      attributes << pointId << static_cast<int>( observations.size() ) << none << none << none << none << none << none << none << none << none << status
                 << QString::fromStdString( s.message );
    }
    else
    {
      ++intersected;
      QString suspect;
      for ( size_t i = 0; i < s.residuals.size(); ++i )
        if ( s.residuals[i].suspect )
          suspect = table.rows[rows[static_cast<int>( i )]].imageId;
      f.setGeometry( QgsGeometry( new QgsPoint( s.point.x(), s.point.y(), s.point.z() ) ) );
      attributes << pointId << static_cast<int>( observations.size() ) << s.sigmaM.x() << s.sigmaM.y() << s.sigmaM.z() << s.rmsPx << s.maxResidualPx
                 << s.maxRayAngleDeg << s.sigma0 << s.grossError << ( suspect.isEmpty() ? none : QVariant( suspect ) ) << status << none;
    }
    const GeoStationProcessing::ObservationRecord &first = table.rows[rows.first()];
    for ( int e : carried )
      attributes << first.extra.value( e );
    f.setAttributes( attributes );
    features << f;
    feedback->setProgress( 90.0 * ( k + 1 ) / order.size() );
  }
  if ( intersected == 0 )
    throw QgsProcessingException( order.isEmpty() ? QObject::tr( "The observations table is empty." )
                                  : QObject::tr( "No point could be intersected: %1" ).arg( skipped.mid( 0, 5 ).join( QLatin1String( "; " ) ) ) );

  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::PointZ, crs );
  for ( QgsFeature &f : features )
    sink.add( f );
  sink.close( true ); // a point seen once: its row, no NaN
  feedback->setProgress( 100 );

  int grossErrors = 0;
  for ( const QgsFeature &f : features )
    grossErrors += f.attribute( QStringLiteral( "gross_error" ) ).toBool() ? 1 : 0;
  feedback->pushInfo( QObject::tr( "%1 of %2 points intersected from %3 observations (%4)." ).arg( intersected ).arg( features.size() ).arg( table.rows.size() )
                      .arg( statusCounts.text() ) );
  if ( grossErrors )
    feedback->pushWarning( QObject::tr( "%1 points show a gross error (see gross_error and suspect_image)." ).arg( grossErrors ) );
  if ( !skipped.isEmpty() )
    feedback->pushWarning( QObject::tr( "%1 points cannot be intersected (kept with their status and message, without geometry): %2" ).arg( skipped.size() ).arg( skipped.mid( 0, 10 ).join( QLatin1String( "; " ) ) ) );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), sink.destination() );
  outputs.insert( QStringLiteral( "POINT_COUNT" ), static_cast<qlonglong>( intersected ) );
  outputs.insert( QStringLiteral( "SKIPPED_COUNT" ), skipped.size() );
  return outputs;
}

} // namespace GeoStationProcessing
