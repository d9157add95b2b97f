/***************************************************************************
  measurementstore.cpp
 ***************************************************************************/
#include "measurementstore.h"

#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QFileInfo>

#include <cpl_error.h>
#include <gdal.h>

#include <qgslayertree.h>
#include <qgslinestring.h>
#include <qgspolygon.h>
#include <qgsproject.h>
#include <qgsproviderregistry.h>
#include <qgsvectordataprovider.h>
#include <qgsvectorfilewriter.h>
#include <qgsvectorlayer.h>
#include <qgsvectorlayereditbuffer.h>

#include "multiviewsession.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace
{
  const QString sGroupName = QStringLiteral( "GeoStation measurements" );
  const QString sVerticesName = QLatin1String( fs::kVerticesTable );

  int methodRank( geostation::VertexMethod method )
  {
    switch ( method )
    {
      case geostation::VertexMethod::Intersection:
        return 0;
      case geostation::VertexMethod::MonoplotDem:
        return 1;
      case geostation::VertexMethod::RoadPlane:
        return 2;
    }
    return 0;
  }

  //! The vector layer if it is a layer of the GeoPackage `target` (absolute path), with its layer name.
  QgsVectorLayer *layerOfFile( QgsMapLayer *layer, const QString &target, QString *layerName )
  {
    QgsVectorLayer *vl = qobject_cast<QgsVectorLayer *>( layer );
    if ( !vl || vl->providerType() != QLatin1String( "ogr" ) )
      return nullptr;
    const QVariantMap parts = QgsProviderRegistry::instance()->decodeUri( QStringLiteral( "ogr" ), vl->source() );
    *layerName = parts.value( QStringLiteral( "layerName" ) ).toString();
    return QFileInfo( parts.value( QStringLiteral( "path" ) ).toString() ).absoluteFilePath() == target ? vl : nullptr;
  }

  /**
   * Removes the file if it is not a GeoPackage GDAL can open: the empty
   * SQLite file the OGR provider leaves where it tried to reopen a
   * GeoPackage that had gone (called only where the file was gone before).
   */
  void removeStrayFile( const QString &file )
  {
    if ( !QFileInfo::exists( file ) )
      return;
    const char *const drivers[] = { "GPKG", nullptr };
    CPLPushErrorHandler( CPLQuietErrorHandler );
    GDALDatasetH ds = GDALOpenEx( file.toUtf8().constData(), GDAL_OF_VECTOR | GDAL_OF_READONLY, drivers, nullptr, nullptr );
    CPLPopErrorHandler();
    if ( ds )
      GDALClose( ds );
    else
      QFile::remove( file );
  }

  //! Adds the fields a layer lacks (a class got new attributes); false if its provider refuses.
  bool addMissingFields( QgsVectorLayer *layer, const QgsFields &fields )
  {
    QgsFields missing;
    for ( const QgsField &f : fields )
      if ( layer->fields().indexFromName( f.name() ) < 0 )
        missing.append( f );
    if ( missing.isEmpty() )
      return true;
    if ( !layer->dataProvider()->addAttributes( missing.toList() ) )
      return false;
    layer->updateFields();
    return true;
  }
}

QString GeoStationMeasuredFeature::method() const
{
  if ( !featureMethod.isEmpty() )
    return featureMethod;
  geostation::VertexMethod weakest = geostation::VertexMethod::Intersection;
  for ( const geostation::MeasuredVertex &v : vertices )
    if ( methodRank( v.method ) > methodRank( weakest ) )
      weakest = v.method;
  return QString::fromStdString( geostation::vertexMethodName( weakest ) );
}

int GeoStationMeasuredFeature::imageCount() const
{
  QSet<QString> ids;
  for ( const geostation::MeasuredVertex &v : vertices )
    for ( const std::string &id : v.imageIds )
      ids.insert( QString::fromStdString( id ) );
  return ids.size();
}

GeoStationMeasurementStore::GeoStationMeasurementStore( GeoStationMultiviewSession *session, QgsProject *project, QObject *parent )
  : QObject( parent )
  , mSession( session )
  , mProject( project )
{
}

QgsFields GeoStationMeasurementStore::featureFields( const GeoStationFeatureClass &featureClass )
{
  QgsFields fields;
  fields.append( QgsField( QLatin1String( fs::kClass ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kStation ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kAcquired ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kMeasured ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kImageCount ), QVariant::Int ) );
  fields.append( QgsField( QLatin1String( fs::kSigmaX ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kSigmaY ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kSigmaZ ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kMethod ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kMeasurementId ), QVariant::String ) );
  for ( auto it = featureClass.attributes.constBegin(); it != featureClass.attributes.constEnd(); ++it )
    fields.append( QgsField( it.key(), QVariant::String ) );
  return fields;
}

QgsFields GeoStationMeasurementStore::vertexFields()
{
  QgsFields fields;
  fields.append( QgsField( QLatin1String( fs::kFeatureFid ), QVariant::LongLong ) );
  fields.append( QgsField( QLatin1String( fs::kVertex ), QVariant::Int ) );
  for ( const char *name : { fs::kX, fs::kY, fs::kZ, fs::kSx, fs::kSy, fs::kSz } )
    fields.append( QgsField( QString::fromLatin1( name ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kImageIds ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kResidualsPx ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kLayer ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kMethod ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kMeasurementId ), QVariant::String ) );
  return fields;
}

bool GeoStationMeasurementStore::checkWritable( QString *error ) const
{
  const QString target = mSession->targetGeoPackage();
  const auto fail = [error]( const QString &why )
  {
    if ( error )
      *error = why;
    return false;
  };
  if ( target.isEmpty() )
    return fail( tr( "Choose the GeoPackage the measurements go to (GeoStation ▸ Measurement GeoPackage…)." ) );
  if ( !target.endsWith( QLatin1String( ".gpkg" ), Qt::CaseInsensitive ) )
    return fail( tr( "The measurement file %1 is not a GeoPackage (.gpkg)." ).arg( target ) );
  const QFileInfo file( target );
  // no write permission for anyone counts as read-only even where the operator could override it (root)
  const auto writable = []( const QFileInfo &info )
  {
    return info.isWritable() && ( info.permissions() & ( QFileDevice::WriteOwner | QFileDevice::WriteGroup | QFileDevice::WriteOther ) );
  };
  if ( file.exists() && !writable( file ) )
    return fail( tr( "The measurement GeoPackage %1 is read-only: measuring would lose the features. Choose another file or make it writable." ).arg( target ) );
  const QFileInfo folder( file.absolutePath() );
  if ( !folder.exists() || !writable( folder ) )
    return fail( tr( "The folder %1 of the measurement GeoPackage cannot be written." ).arg( file.absolutePath() ) );
  return true;
}

bool GeoStationMeasurementStore::setTarget( const QString &path, QString *error )
{
  const QString previous = mSession->targetGeoPackage();
  mSession->setTargetGeoPackage( path );
  if ( checkWritable( error ) )
    return true;
  mSession->setTargetGeoPackage( previous );
  return false;
}

QgsVectorLayer *GeoStationMeasurementStore::openOrCreate( const QString &layerName, const QgsFields &fields, QgsWkbTypes::Type type, QString *error )
{
  if ( !checkWritable( error ) )
    return nullptr;
  const QString target = QFileInfo( mSession->targetGeoPackage() ).absoluteFilePath();
  // the project's layer, if it is there already
  const auto extend = [&]( QgsVectorLayer * vl )
  {
    if ( addMissingFields( vl, fields ) )
      return true;
    if ( error )
      *error = tr( "The fields of %1 cannot be extended in %2." ).arg( layerName, target );
    return false;
  };
  for ( QgsMapLayer *layer : mProject->mapLayers() )
  {
    QString name;
    QgsVectorLayer *vl = layerOfFile( layer, target, &name );
    if ( vl && name == layerName )
    {
      if ( !extend( vl ) )
        return nullptr;
      watch( vl );
      return vl;
    }
  }
  const QString uri = QStringLiteral( "%1|layername=%2" ).arg( target, layerName );
  QgsVectorLayer::LayerOptions layerOptions( mProject->transformContext() );
  layerOptions.skipCrsValidation = true;
  auto layer = std::make_unique<QgsVectorLayer>( uri, layerName, QStringLiteral( "ogr" ), layerOptions );
  if ( !layer->isValid() )
  {
    QgsVectorFileWriter::SaveVectorOptions options;
    options.driverName = QStringLiteral( "GPKG" );
    options.layerName = layerName;
    options.actionOnExistingFile = QFileInfo::exists( target ) ? QgsVectorFileWriter::CreateOrOverwriteLayer : QgsVectorFileWriter::CreateOrOverwriteFile;
    QString newFile, newLayer;
    std::unique_ptr<QgsVectorFileWriter> writer( QgsVectorFileWriter::create( target, fields, type, mSession->crs(), mProject->transformContext(), options,
        QgsFeatureSink::SinkFlags(), &newFile, &newLayer ) );
    if ( !writer || writer->hasError() != QgsVectorFileWriter::NoError )
    {
      if ( error )
        *error = tr( "The layer %1 cannot be created in %2: %3" ).arg( layerName, target, writer ? writer->errorMessage() : tr( "unknown error" ) );
      return nullptr;
    }
    writer.reset();
    layer = std::make_unique<QgsVectorLayer>( uri, layerName, QStringLiteral( "ogr" ), layerOptions );
    if ( !layer->isValid() )
    {
      if ( error )
        *error = tr( "The layer %1 was created in %2 but cannot be opened." ).arg( layerName, target );
      return nullptr;
    }
  }
  else
  {
    if ( layer->fields().indexFromName( fields.at( 0 ).name() ) < 0 )
    {
      if ( error )
        *error = tr( "%1 in %2 is not a GeoStation layer (it has no field %3)." ).arg( layerName, target, fields.at( 0 ).name() );
      return nullptr;
    }
    if ( !extend( layer.get() ) )
      return nullptr;
  }
  QgsLayerTreeGroup *group = mProject->layerTreeRoot()->findGroup( sGroupName );
  if ( !group )
    group = mProject->layerTreeRoot()->insertGroup( 0, sGroupName );
  QgsVectorLayer *added = layer.release();
  mProject->addMapLayer( added, false );
  group->addLayer( added );
  watch( added );
  emit measurementsChanged();
  return added;
}

QgsVectorLayer *GeoStationMeasurementStore::layerFor( const GeoStationFeatureClass &featureClass, QString *error )
{
  const QgsWkbTypes::Type type = featureClass.geometry == GeoStationFeatureClass::Geometry::Point ? QgsWkbTypes::PointZ
                                 : featureClass.geometry == GeoStationFeatureClass::Geometry::Line ? QgsWkbTypes::LineStringZ
                                 : QgsWkbTypes::PolygonZ;
  QgsVectorLayer *layer = openOrCreate( featureClass.layerName(), featureFields( featureClass ), type, error );
  if ( layer && QgsWkbTypes::geometryType( layer->wkbType() ) != QgsWkbTypes::geometryType( type ) )
  {
    if ( error )
      *error = tr( "The layer %1 holds %2 geometries, the class %3 measures %4s." )
               .arg( featureClass.layerName(), QgsWkbTypes::geometryDisplayString( layer->geometryType() ), featureClass.name,
                     GeoStationFeatureClass::geometryName( featureClass.geometry ) );
    return nullptr;
  }
  return layer;
}

QgsVectorLayer *GeoStationMeasurementStore::verticesTable( QString *error )
{
  return openOrCreate( sVerticesName, vertexFields(), QgsWkbTypes::NoGeometry, error );
}

QList<QgsVectorLayer *> GeoStationMeasurementStore::measurementLayers() const
{
  QList<QgsVectorLayer *> layers;
  const QString target = QFileInfo( mSession->targetGeoPackage() ).absoluteFilePath();
  if ( mSession->targetGeoPackage().isEmpty() )
    return layers;
  for ( QgsMapLayer *layer : mProject->mapLayers() )
  {
    QString name;
    QgsVectorLayer *vl = layerOfFile( layer, target, &name );
    if ( vl && vl->isSpatial() && name != sVerticesName )
      layers << vl;
  }
  return layers;
}

void GeoStationMeasurementStore::watch( QgsVectorLayer *layer )
{
  for ( const QPointer<QgsVectorLayer> &w : std::as_const( mWatched ) )
    if ( w == layer )
      return;
  mWatched << layer;
  if ( layer->name() == sVerticesName )
    return;
  connect( layer, &QgsVectorLayer::committedFeaturesAdded, this, [this, layer]( const QString &, const QgsFeatureList &added ) { writeVertices( layer, added ); } );
  // the views redraw the features when they change, in the edit buffer or in the file
  for ( auto signal : { &QgsVectorLayer::featureAdded, &QgsVectorLayer::featureDeleted } )
    connect( layer, signal, this, &GeoStationMeasurementStore::measurementsChanged );
  connect( layer, &QgsVectorLayer::geometryChanged, this, &GeoStationMeasurementStore::measurementsChanged );
  connect( layer, &QgsVectorLayer::afterRollBack, this, &GeoStationMeasurementStore::measurementsChanged );
  connect( layer, &QgsVectorLayer::dataSourceChanged, this, &GeoStationMeasurementStore::measurementsChanged );
}

GeoStationMeasurementStore::~GeoStationMeasurementStore()
{
  // (with the GeoPackage gone, the features cannot be saved into it either: no new file is made for their vertices)
  if ( mPendingVertices.isEmpty() || !QFileInfo::exists( mSession->targetGeoPackage() ) )
    return;
  for ( const QPointer<QgsVectorLayer> &layer : std::as_const( mWatched ) )
  {
    if ( !layer || !layer->editBuffer() )
      continue;
    QList<QPair<QVariant, GeoStationMeasuredFeature>> toWrite;
    for ( const QgsFeature &f : layer->editBuffer()->addedFeatures() )
    {
      const auto it = mPendingVertices.constFind( f.attribute( QLatin1String( fs::kMeasurementId ) ).toString() );
      if ( it != mPendingVertices.constEnd() )
        toWrite << qMakePair( QVariant(), it.value() );
    }
    if ( !toWrite.isEmpty() )
      writeVertexRows( layer->name(), toWrite );
  }
}

void GeoStationMeasurementStore::writeVertices( QgsVectorLayer *layer, const QgsFeatureList &added )
{
  QList<QPair<QVariant, GeoStationMeasuredFeature>> toWrite;
  for ( const QgsFeature &f : added )
  {
    const QString id = f.attribute( QLatin1String( fs::kMeasurementId ) ).toString();
    auto it = mPendingVertices.find( id );
    if ( it != mPendingVertices.end() )
      toWrite << qMakePair( QVariant( f.id() ), it.value() );
  }
  if ( !toWrite.isEmpty() )
    writeVertexRows( layer->name(), toWrite );
}

void GeoStationMeasurementStore::writeVertexRows( const QString &layerName, const QList<QPair<QVariant, GeoStationMeasuredFeature>> &toWrite )
{
  QString error;
  QgsVectorLayer *table = verticesTable( &error );
  if ( !table )
    return;
  const bool wasEditing = table->isEditable();
  if ( !wasEditing && !table->startEditing() )
    return;
  const QgsFields fields = table->fields();
  for ( const auto &[fid, feature] : toWrite )
  {
    for ( int i = 0; i < feature.vertices.size(); ++i )
    {
      const geostation::MeasuredVertex &v = feature.vertices[i];
      QgsFeature row( fields );
      QStringList images, residuals;
      for ( size_t k = 0; k < v.imageIds.size(); ++k )
      {
        images << QString::fromStdString( v.imageIds[k] );
        if ( k < v.residualsPx.size() )
          residuals << QStringLiteral( "%1 %2" ).arg( v.residualsPx[k].x(), 0, 'f', 3 ).arg( v.residualsPx[k].y(), 0, 'f', 3 );
      }
      row.setAttribute( QLatin1String( fs::kFeatureFid ), fid );
      row.setAttribute( QLatin1String( fs::kVertex ), i );
      row.setAttribute( QLatin1String( fs::kX ), v.point.x() );
      row.setAttribute( QLatin1String( fs::kY ), v.point.y() );
      row.setAttribute( QLatin1String( fs::kZ ), v.point.z() );
      row.setAttribute( QLatin1String( fs::kSx ), v.sigmaM.x() );
      row.setAttribute( QLatin1String( fs::kSy ), v.sigmaM.y() );
      row.setAttribute( QLatin1String( fs::kSz ), v.sigmaM.z() );
      row.setAttribute( QLatin1String( fs::kImageIds ), images.join( ';' ) );
      row.setAttribute( QLatin1String( fs::kResidualsPx ), residuals.join( ';' ) );
      row.setAttribute( QLatin1String( fs::kLayer ), layerName );
      row.setAttribute( QLatin1String( fs::kMethod ), QString::fromStdString( geostation::vertexMethodName( v.method ) ) );
      row.setAttribute( QLatin1String( fs::kMeasurementId ), feature.measurementId );
      table->addFeature( row );
    }
    mPendingVertices.remove( feature.measurementId );
  }
  if ( !wasEditing )
    table->commitChanges();
}

GeoStationMeasurementStore::Result GeoStationMeasurementStore::addFeature( const GeoStationMeasuredFeature &feature )
{
  Result result;
  const GeoStationFeatureClass *featureClass = mSession->findClass( feature.className );
  if ( !featureClass )
  {
    result.message = tr( "There is no feature class %1." ).arg( feature.className );
    return result;
  }
  if ( feature.vertices.size() < featureClass->minimumVertices() )
  {
    result.message = tr( "A %1 needs at least %2 vertices." ).arg( GeoStationFeatureClass::geometryName( featureClass->geometry ) ).arg( featureClass->minimumVertices() );
    return result;
  }
  QString error;
  QgsVectorLayer *layer = layerFor( *featureClass, &error );
  if ( !layer )
  {
    result.message = error;
    return result;
  }
  QgsGeometry geometry;
  QVector<QgsPoint> points;
  for ( const geostation::MeasuredVertex &v : feature.vertices )
    points << QgsPoint( v.point.x(), v.point.y(), v.point.z() );
  if ( featureClass->geometry == GeoStationFeatureClass::Geometry::Point )
    geometry = QgsGeometry( new QgsPoint( points.first() ) );
  else if ( featureClass->geometry == GeoStationFeatureClass::Geometry::Line )
    geometry = QgsGeometry( new QgsLineString( points ) );
  else
  {
    points << points.first();
    QgsPolygon *polygon = new QgsPolygon();
    polygon->setExteriorRing( new QgsLineString( points ) );
    geometry = QgsGeometry( polygon );
  }
  double sx = 0, sy = 0, sz = 0;
  for ( const geostation::MeasuredVertex &v : feature.vertices )
  {
    sx = std::max( sx, v.sigmaM.x() );
    sy = std::max( sy, v.sigmaM.y() );
    sz = std::max( sz, v.sigmaM.z() );
  }
  QgsFeature f( layer->fields() );
  f.setGeometry( geometry );
  const auto set = [&]( const QString &name, const QVariant &value )
  {
    const int i = layer->fields().indexFromName( name );
    if ( i >= 0 )
      f.setAttribute( i, value );
  };
  for ( auto it = featureClass->attributes.constBegin(); it != featureClass->attributes.constEnd(); ++it )
    set( it.key(), it.value() );
  set( QLatin1String( fs::kClass ), featureClass->name );
  set( QLatin1String( fs::kStation ), feature.station );
  set( QLatin1String( fs::kAcquired ), feature.acquired );
  set( QLatin1String( fs::kMeasured ), feature.measured );
  set( QLatin1String( fs::kImageCount ), feature.imageCount() );
  set( QLatin1String( fs::kSigmaX ), sx );
  set( QLatin1String( fs::kSigmaY ), sy );
  set( QLatin1String( fs::kSigmaZ ), sz );
  set( QLatin1String( fs::kMethod ), feature.method() );
  set( QLatin1String( fs::kMeasurementId ), feature.measurementId );

  // the file removed or moved behind QGIS's back: a commit would fail, and leave an empty file that is no GeoPackage in its place
  const QString file = QFileInfo( mSession->targetGeoPackage() ).absoluteFilePath();
  const bool fileGone = !QFileInfo::exists( file );
  const bool operatorEditing = layer->isEditable();
  if ( !operatorEditing && !layer->startEditing() )
  {
    result.message = tr( "The layer %1 cannot be edited (is the GeoPackage read-only?)." ).arg( layer->name() );
    return result;
  }
  mPendingVertices.insert( feature.measurementId, feature );
  if ( !layer->addFeature( f ) )
  {
    mPendingVertices.remove( feature.measurementId );
    if ( !operatorEditing )
      layer->rollBack();
    result.message = tr( "The layer %1 refused the feature." ).arg( layer->name() );
    return result;
  }
  result.ok = true;
  if ( fileGone )
  {
    removeStrayFile( file );
    result.message = tr( "The measurement GeoPackage %1 is no longer there (moved or deleted?): the feature stays in the edit buffer of %2, as does every one "
                         "measured after it. Save them with Export ▸ Save Features As… (with the file gone, the layer's edits cannot be saved into it), "
                         "then choose a measurement GeoPackage again." )
                     .arg( file, layer->name() );
    emit measurementsChanged();
    return result;
  }
  if ( operatorEditing )
  {
    result.message = tr( "Added to %1 in your edit session: save the layer's edits to write it." ).arg( layer->name() );
    emit measurementsChanged();
    return result;
  }
  if ( !layer->commitChanges() )
  {
    // keep it in the edit buffer: nothing is lost, the operator can save later
    result.message = tr( "%1 could not be written (%2); the feature stays in the layer's edit buffer: save the layer once the problem is solved." )
                     .arg( layer->name(), layer->commitErrors().join( QLatin1String( "; " ) ) );
    emit measurementsChanged();
    return result;
  }
  result.committed = true;
  result.message = tr( "Written to %1." ).arg( layer->name() );
  emit measurementsChanged();
  return result;
}
