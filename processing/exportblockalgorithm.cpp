/***************************************************************************
  exportblockalgorithm.cpp - geostation:export_block
 ***************************************************************************/
#include "exportblockalgorithm.h"

#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>

#include "io/blockexport.h"
#include "processingblock.h"
#include "processingtables.h"

namespace GeoStationProcessing
{

namespace
{
  const QStringList sFormats { QStringLiteral( "colmap" ), QStringLiteral( "csv" ) };
}

QString ExportBlockAlgorithm::name() const
{
  return QStringLiteral( "export_block" );
}

QString ExportBlockAlgorithm::displayName() const
{
  return QObject::tr( "Export block (COLMAP, CSV)" );
}

QStringList ExportBlockAlgorithm::tags() const
{
  return QObject::tr( "photogrammetry,export,colmap,csv,exterior orientation,block" ).split( ',' );
}

QString ExportBlockAlgorithm::group() const
{
  return QObject::tr( "Block" );
}

QString ExportBlockAlgorithm::groupId() const
{
  return QStringLiteral( "block" );
}

QString ExportBlockAlgorithm::helpText() const
{
  return QObject::tr( "Hands an oriented block back.\n\n"
                      "FORMAT colmap writes a COLMAP text model (cameras.txt, images.txt, points3D.txt) into the folder "
                      "OUTPUT. Image names are the block's image paths relative to the block file, so COLMAP finds the "
                      "images with the block's folder as its image path. Cameras with the lens model none or opencv "
                      "convert exactly; brown_photo cameras, scanned photos and images not yet oriented are left out "
                      "and named in the log. OBSERVATIONS (point_id, image_id, col, row) with POINTS (point_id, X, Y, Z) "
                      "add tie points.\n\n"
                      "FORMAT csv writes the file OUTPUT with one row per image: image_id, camera, station, path, X, Y, Z, "
                      "omega, phi, kappa (metres and degrees, the block's conventions) and their a priori sigmas." );
}

ExportBlockAlgorithm *ExportBlockAlgorithm::createInstance() const
{
  return new ExportBlockAlgorithm();
}

void ExportBlockAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "FORMAT" ), QObject::tr( "Format" ), sFormats, false, QStringLiteral( "colmap" ), false, true ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "OBSERVATIONS" ), QObject::tr( "Tie-point observations (point_id, image_id, col, row)" ),
                QList<int>() << QgsProcessing::TypeVector, QVariant(), true ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "POINTS" ), QObject::tr( "Tie points (point_id, X, Y, Z)" ), QList<int>() << QgsProcessing::TypeVector, QVariant(), true ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "OUTPUT" ), QObject::tr( "COLMAP model folder, or CSV file" ), QObject::tr( "All files (*)" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "IMAGES_EXPORTED" ), QObject::tr( "Images exported" ) ) );
}

QVariantMap ExportBlockAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const bool colmap = parameterAsEnumString( parameters, QStringLiteral( "FORMAT" ), context ) == QLatin1String( "colmap" );
  const QString output = parameterAsFileOutput( parameters, QStringLiteral( "OUTPUT" ), context );
  if ( output.isEmpty() )
    throw QgsProcessingException( QObject::tr( "OUTPUT: give the folder (colmap) or file (csv) to write." ) );

  std::vector<geostation::ImportedTiePoint> tiePoints;
  std::vector<geostation::ImportedObservation> observations;
  std::unique_ptr<QgsProcessingFeatureSource> observationSource( parameterAsSource( parameters, QStringLiteral( "OBSERVATIONS" ), context ) );
  std::unique_ptr<QgsProcessingFeatureSource> pointSource( parameterAsSource( parameters, QStringLiteral( "POINTS" ), context ) );
  if ( colmap && ( observationSource || pointSource ) )
  {
    if ( !observationSource || !pointSource )
      throw QgsProcessingException( QObject::tr( "Tie points need both OBSERVATIONS and POINTS." ) );
    const GeoStationProcessing::ObservationTable table = GeoStationProcessing::readObservations( observationSource.get(), QObject::tr( "OBSERVATIONS" ), feedback );
    for ( const GeoStationProcessing::ObservationRecord &r : table.rows )
      observations.push_back( { r.pointId.toStdString(), r.imageId.toStdString(), r.pixel } );
    const QgsCoordinateReferenceSystem crs = GeoStationProcessing::blockCrs( block );
    for ( const GeoStationProcessing::GroundPointRecord &p : GeoStationProcessing::readGroundPoints( pointSource.get(), QObject::tr( "POINTS" ), crs, context.transformContext(), feedback ) )
      tiePoints.push_back( { p.pointId.toStdString(), p.world, -1.0 } );
  }

  geostation::BlockExportSummary summary;
  summary = colmap ? geostation::exportBlockAsColmap( block, output.toStdString(), tiePoints, observations )
                   : geostation::exportBlockAsCsv( block, output.toStdString() );
  for ( const std::string &s : summary.dropped )
    feedback->reportError( QObject::tr( "Left out: %1" ).arg( QString::fromStdString( s ) ) );
  feedback->pushInfo( colmap ? QObject::tr( "COLMAP model written to %1: %2 camera(s), %3 image(s), %4 tie point(s)" ).arg( output ).arg( summary.cameras ).arg( summary.images ).arg( summary.tiePoints )
                             : QObject::tr( "%1 oriented image(s) written to %2" ).arg( summary.images ).arg( output ) );
  feedback->setProgress( 100 );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), output );
  outputs.insert( QStringLiteral( "IMAGES_EXPORTED" ), summary.images );
  return outputs;
}

} // namespace GeoStationProcessing
