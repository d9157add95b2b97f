/***************************************************************************
  extractionreview.cpp - reviewing an extracted road network in QGIS
 ***************************************************************************/
#include "extractionreview.h"

#include <QDateTime>
#include <QUuid>

#include <qgsexception.h>
#include <qgsgeometry.h>
#include <qgsvectordataprovider.h>
#include <qgsvectorlayer.h>

#include "measurementstore.h"
#include "multiviewsession.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

GeoStationExtractionReview::GeoStationExtractionReview( GeoStationMultiviewSession *session, GeoStationMeasurementStore *store, QObject *parent )
  : QObject( parent ), mSession( session ), mStore( store )
{
}

bool GeoStationExtractionReview::isExtractedRoadsLayer( const QgsVectorLayer *layer )
{
  if ( !layer || !layer->isValid() || layer->geometryType() != QgsWkbTypes::LineGeometry || !QgsWkbTypes::hasZ( layer->wkbType() ) )
    return false;
  const QgsFields fields = layer->fields();
  return fields.lookupField( QLatin1String( fs::kLineId ) ) >= 0 && fields.lookupField( QLatin1String( fs::kAcceptedIn ) ) >= 0
         && fields.lookupField( QLatin1String( fs::kSigmaMax ) ) >= 0;
}

bool GeoStationExtractionReview::mark( QgsVectorLayer *layer, QgsFeatureId fid, const QString &decision )
{
  int field = layer->fields().lookupField( QLatin1String( fs::kReview ) );
  if ( field < 0 )
  {
    if ( layer->isEditable() )
      layer->addAttribute( QgsField( QLatin1String( fs::kReview ), QVariant::String ) );
    else if ( !( layer->dataProvider()->capabilities() & QgsVectorDataProvider::AddAttributes )
              || !layer->dataProvider()->addAttributes( { QgsField( QLatin1String( fs::kReview ), QVariant::String ) } ) )
      return false;
    layer->updateFields();
    field = layer->fields().lookupField( QLatin1String( fs::kReview ) );
  }
  if ( field < 0 )
    return false;
  if ( layer->isEditable() )
    return layer->changeAttributeValue( fid, field, decision );
  return layer->dataProvider()->changeAttributeValues( { { fid, { { field, decision } } } } ) && ( layer->triggerRepaint(), true );
}

bool GeoStationExtractionReview::review( QgsVectorLayer *layer, QgsFeatureId fid, bool accept )
{
  if ( !isExtractedRoadsLayer( layer ) )
  {
    emit message( tr( "This is not a layer of extracted roads (geostation:extract_roads' OUTPUT)." ), true );
    return false;
  }
  QgsFeature f;
  if ( !layer->getFeatures( QgsFeatureRequest( fid ) ).nextFeature( f ) || f.geometry().isEmpty() )
  {
    emit message( tr( "The line is no longer in the layer." ), true );
    return false;
  }
  const int reviewField = layer->fields().lookupField( QLatin1String( fs::kReview ) );
  const QString previous = reviewField >= 0 ? f.attribute( reviewField ).toString() : QString();
  const QString lineId = f.attribute( QLatin1String( fs::kLineId ) ).toString();
  if ( previous == QLatin1String( "accepted" ) )
  {
    emit message( tr( "Line %1 was accepted already." ).arg( lineId ), false );
    return false;
  }
  if ( !accept )
  {
    const bool marked = mark( layer, fid, QStringLiteral( "rejected" ) );
    emit message( marked ? tr( "Line %1 rejected." ).arg( lineId ) : tr( "Line %1 rejected, but the decision could not be written to %2 (read-only)." ).arg( lineId, layer->name() ), !marked );
    return marked;
  }
  const GeoStationFeatureClass *featureClass = mSession->findClass( mSession->currentClass() );
  if ( !featureClass || featureClass->geometry != GeoStationFeatureClass::Geometry::Line )
  {
    emit message( tr( "Choose a line class to copy accepted roads into." ), true );
    return false;
  }
  GeoStationMeasuredFeature measured;
  measured.className = featureClass->name;
  measured.featureMethod = QStringLiteral( "extracted" );
  measured.measured = QDateTime::currentDateTimeUtc().toString( Qt::ISODateWithMs );
  measured.measurementId = QUuid::createUuid().toString( QUuid::WithoutBraces );
  const double sigma = f.attribute( QLatin1String( fs::kSigmaMax ) ).toDouble();
  for ( auto v = f.geometry().vertices_begin(); v != f.geometry().vertices_end(); ++v )
  {
    geostation::MeasuredVertex vertex;
    vertex.status = geostation::MeasuredVertex::Status::Ok;
    vertex.method = geostation::VertexMethod::Intersection;
    vertex.point = Eigen::Vector3d( ( *v ).x(), ( *v ).y(), ( *v ).z() );
    vertex.sigmaM = Eigen::Vector3d::Constant( sigma );
    measured.vertices << vertex;
  }
  if ( measured.vertices.size() < 2 )
  {
    emit message( tr( "Line %1 has fewer than two vertices." ).arg( lineId ), true );
    return false;
  }
  const GeoStationMeasurementStore::Result result = mStore->addFeature( measured );
  if ( !result.ok )
  {
    emit message( tr( "Line %1 could not be copied into %2: %3" ).arg( lineId, featureClass->name, result.message ), true );
    return false;
  }
  const bool marked = mark( layer, fid, QStringLiteral( "accepted" ) );
  emit message( tr( "Line %1 accepted into %2 (%3 vertices): %4%5" ).arg( lineId, featureClass->name ).arg( measured.vertices.size() ).arg( result.message,
                marked ? QString() : tr( "; the decision could not be written to %1" ).arg( layer->name() ) ), !result.committed || !marked );
  return true;
}

