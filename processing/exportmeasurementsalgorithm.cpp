/***************************************************************************
  exportmeasurementsalgorithm.cpp - geostation:export_measurements
  -------------------------------------------------------------------------
  The measurement GeoPackage for ArcGIS and CAD users, written by QGIS's
  own writers: every feature layer as a Shapefile (attributes and Z; field
  names cut to the format's 10 characters, the cut names listed in the
  log) and as a DXF (3D points and polylines on a DXF layer named after
  the class). DXF entities carry no attribute table, so each DXF gets a
  CSV of the attributes keyed by the entity handle the DXF writer gave the
  entity (read back from the written file). The vertex table goes to CSV.
  Files are written into a staging folder and moved into place only when
  all of them are complete.
 ***************************************************************************/
#include "exportmeasurementsalgorithm.h"

#include <QDir>
#include <QFileInfo>
#include <QTemporaryDir>

#include <gdal.h>

#include <qgsfeatureiterator.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsvectorfilewriter.h>
#include <qgsvectorlayer.h>

namespace GeoStationProcessing
{

namespace
{
  //! The layers of a GeoPackage (name, has geometry).
  QList<QPair<QString, bool>> geoPackageLayers( const QString &path )
  {
    QList<QPair<QString, bool>> layers;
    GDALDatasetH ds = GDALOpenEx( path.toUtf8().constData(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr );
    if ( !ds )
      return layers;
    for ( int i = 0; i < GDALDatasetGetLayerCount( ds ); ++i )
    {
      OGRLayerH layer = GDALDatasetGetLayer( ds, i );
      layers << qMakePair( QString::fromUtf8( OGR_L_GetName( layer ) ), OGR_L_GetGeomType( layer ) != wkbNone );
    }
    GDALClose( ds );
    return layers;
  }

  void write( QgsVectorLayer *layer, const QString &path, const QString &driver, QgsProcessingContext &context, const QgsAttributeList &attributes = QgsAttributeList(),
              bool onlySelectedAttributes = false )
  {
    QgsVectorFileWriter::SaveVectorOptions options;
    options.driverName = driver;
    options.fileEncoding = QStringLiteral( "UTF-8" );
    if ( onlySelectedAttributes )
      options.attributes = attributes;
    QString error, newFile, newLayer;
    const QgsVectorFileWriter::WriterError result = QgsVectorFileWriter::writeAsVectorFormatV3( layer, path, context.transformContext(), options, &error, &newFile, &newLayer );
    if ( result != QgsVectorFileWriter::NoError )
      throw QgsProcessingException( QObject::tr( "%1 cannot be written: %2" ).arg( QFileInfo( path ).fileName(), error ) );
  }

  QString csvField( const QVariant &value )
  {
    QString text = value.isNull() ? QString() : value.toString();
    if ( text.contains( ',' ) || text.contains( '"' ) || text.contains( '\n' ) )
      text = '"' + text.replace( '"', QLatin1String( "\"\"" ) ) + '"';
    return text;
  }
}

QString ExportMeasurementsAlgorithm::name() const
{
  return QStringLiteral( "export_measurements" );
}

QString ExportMeasurementsAlgorithm::displayName() const
{
  return QObject::tr( "Export measurements to Shapefile and DXF" );
}

QStringList ExportMeasurementsAlgorithm::tags() const
{
  return QObject::tr( "export,shapefile,dxf,cad,arcgis,measurements,multiview" ).split( ',' );
}

QString ExportMeasurementsAlgorithm::group() const
{
  return QObject::tr( "Measurement" );
}

QString ExportMeasurementsAlgorithm::groupId() const
{
  return QStringLiteral( "measurement" );
}

QString ExportMeasurementsAlgorithm::helpText() const
{
  return QObject::tr( "Writes the layers of a GeoStation measurement GeoPackage for ArcGIS and CAD users with QGIS's own writers. "
                      "Every feature layer LAYER becomes LAYER.shp (attributes and Z kept; Shapefile field names are cut to 10 "
                      "characters, e.g. measurement_id → measuremen) and LAYER.dxf (3D points and polylines on a DXF layer "
                      "named after the layer). DXF has no attribute table: LAYER_dxf_attributes.csv holds every feature's "
                      "attributes keyed by the entity handle of its DXF entity. The vertices table goes to vertices.csv.\n\n"
                      "FORMATS: shp, dxf or both. Nothing is left in OUTPUT_FOLDER if any file fails." );
}

ExportMeasurementsAlgorithm *ExportMeasurementsAlgorithm::createInstance() const
{
  return new ExportMeasurementsAlgorithm();
}

void ExportMeasurementsAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( new QgsProcessingParameterFile( QStringLiteral( "INPUT" ), QObject::tr( "Measurement GeoPackage" ), QgsProcessingParameterFile::File, QStringLiteral( "gpkg" ) ) );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "FORMATS" ), QObject::tr( "Formats" ), { QStringLiteral( "shp" ), QStringLiteral( "dxf" ) }, true,
                QVariantList { QStringLiteral( "shp" ), QStringLiteral( "dxf" ) }, false, true ) );
  addParameter( new QgsProcessingParameterFolderDestination( QStringLiteral( "OUTPUT_FOLDER" ), QObject::tr( "Output folder" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "LAYERS" ), QObject::tr( "Feature layers exported" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "FEATURES" ), QObject::tr( "Features exported" ) ) );
}

QVariantMap ExportMeasurementsAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const QString input = parameterAsFile( parameters, QStringLiteral( "INPUT" ), context );
  const QStringList formats = parameterAsEnumStrings( parameters, QStringLiteral( "FORMATS" ), context );
  const QString folder = parameterAsString( parameters, QStringLiteral( "OUTPUT_FOLDER" ), context );
  if ( !QFileInfo::exists( input ) )
    throw QgsProcessingException( QObject::tr( "The measurement GeoPackage %1 does not exist." ).arg( input ) );
  const QList<QPair<QString, bool>> layers = geoPackageLayers( input );
  if ( layers.isEmpty() )
    throw QgsProcessingException( QObject::tr( "%1 is not a GeoPackage with layers." ).arg( input ) );
  if ( !QDir().mkpath( folder ) )
    throw QgsProcessingException( QObject::tr( "The folder %1 cannot be created." ).arg( folder ) );
  QTemporaryDir staging( QDir( folder ).filePath( QStringLiteral( ".geostation-export-XXXXXX" ) ) );
  if ( !staging.isValid() )
    throw QgsProcessingException( QObject::tr( "The folder %1 cannot be written." ).arg( folder ) );

  QStringList written;
  int exportedLayers = 0;
  long features = 0;
  for ( int i = 0; i < layers.size(); ++i )
  {
    if ( feedback->isCanceled() )
      return {};
    feedback->setProgress( 100.0 * i / layers.size() );
    const QString name = layers[i].first;
    QgsVectorLayer layer( QStringLiteral( "%1|layername=%2" ).arg( input, name ), name, QStringLiteral( "ogr" ) );
    if ( !layer.isValid() )
      throw QgsProcessingException( QObject::tr( "The layer %1 of %2 cannot be read." ).arg( name, input ) );
    if ( !layers[i].second )
    {
      write( &layer, staging.filePath( name + QStringLiteral( ".csv" ) ), QStringLiteral( "CSV" ), context );
      written << name + QStringLiteral( ".csv" );
      continue;
    }
    ++exportedLayers;
    features += layer.featureCount();
    if ( formats.contains( QStringLiteral( "shp" ) ) )
    {
      write( &layer, staging.filePath( name + QStringLiteral( ".shp" ) ), QStringLiteral( "ESRI Shapefile" ), context );
      for ( const char *suffix : { ".shp", ".shx", ".dbf", ".prj", ".cpg" } )
        if ( QFileInfo::exists( staging.filePath( name + QLatin1String( suffix ) ) ) )
          written << name + QLatin1String( suffix );
      QStringList cut;
      for ( const QgsField &field : layer.fields() )
        if ( field.name().size() > 10 )
          cut << QStringLiteral( "%1 → %2" ).arg( field.name(), field.name().left( 10 ) );
      if ( !cut.isEmpty() )
        feedback->pushInfo( QObject::tr( "%1.shp: field names cut to 10 characters: %2" ).arg( name, cut.join( QLatin1String( ", " ) ) ) );
    }
    if ( formats.contains( QStringLiteral( "dxf" ) ) )
    {
      // the DXF layer of every entity: the measurement layer's name
      const QString uri = QStringLiteral( "%1?crs=%2&field=Layer:string" ).arg( QgsWkbTypes::displayString( layer.wkbType() ), layer.crs().authid() );
      QgsVectorLayer entities( uri, name, QStringLiteral( "memory" ) );
      QgsFeatureList copies;
      QList<QgsFeature> originals;
      QgsFeatureIterator it = layer.getFeatures();
      QgsFeature f;
      while ( it.nextFeature( f ) )
      {
        QgsFeature copy( entities.fields() );
        copy.setGeometry( f.geometry() );
        copy.setAttributes( QgsAttributes() << name );
        copies << copy;
        originals << f;
      }
      entities.dataProvider()->addFeatures( copies );
      const QString dxf = staging.filePath( name + QStringLiteral( ".dxf" ) );
      write( &entities, dxf, QStringLiteral( "DXF" ), context, QgsAttributeList() << 0, true );
      // the handles the writer gave, in the order the features were written
      QgsVectorLayer readBack( dxf, name, QStringLiteral( "ogr" ) );
      QStringList handles;
      QgsFeatureIterator rit = readBack.getFeatures();
      while ( rit.nextFeature( f ) )
        handles << f.attribute( QStringLiteral( "EntityHandle" ) ).toString();
      if ( handles.size() != originals.size() )
        throw QgsProcessingException( QObject::tr( "%1.dxf holds %2 entities for %3 features." ).arg( name ).arg( handles.size() ).arg( originals.size() ) );
      QFile csv( staging.filePath( name + QStringLiteral( "_dxf_attributes.csv" ) ) );
      if ( !csv.open( QIODevice::WriteOnly | QIODevice::Text ) )
        throw QgsProcessingException( QObject::tr( "%1 cannot be written." ).arg( csv.fileName() ) );
      QStringList header { QStringLiteral( "EntityHandle" ), QStringLiteral( "fid" ) };
      for ( const QgsField &field : layer.fields() )
        if ( field.name() != QLatin1String( "fid" ) )
          header << field.name();
      csv.write( header.join( ',' ).toUtf8() + '\n' );
      for ( int k = 0; k < originals.size(); ++k )
      {
        QStringList row { handles[k], QString::number( originals[k].id() ) };
        for ( int a = 0; a < layer.fields().size(); ++a )
          if ( layer.fields().at( a ).name() != QLatin1String( "fid" ) )
            row << csvField( originals[k].attribute( a ) );
        csv.write( row.join( ',' ).toUtf8() + '\n' );
      }
      if ( !csv.flush() )
        throw QgsProcessingException( QObject::tr( "%1 cannot be written (disk full?)." ).arg( csv.fileName() ) );
      written << name + QStringLiteral( ".dxf" ) << name + QStringLiteral( "_dxf_attributes.csv" );
    }
  }
  if ( feedback->isCanceled() )
    return {};
  // all complete: into place
  for ( const QString &file : std::as_const( written ) )
  {
    const QString target = QDir( folder ).filePath( file );
    QFile::remove( target );
    if ( !QFile::rename( staging.filePath( file ), target ) )
      throw QgsProcessingException( QObject::tr( "%1 cannot be moved into %2." ).arg( file, folder ) );
  }
  feedback->pushInfo( QObject::tr( "%1 feature layers (%2 features) exported to %3." ).arg( exportedLayers ).arg( features ).arg( folder ) );
  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT_FOLDER" ), folder );
  outputs.insert( QStringLiteral( "LAYERS" ), exportedLayers );
  outputs.insert( QStringLiteral( "FEATURES" ), static_cast<double>( features ) );
  return outputs;
}

} // namespace GeoStationProcessing
