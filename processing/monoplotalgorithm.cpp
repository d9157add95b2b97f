/***************************************************************************
  monoplotalgorithm.cpp - geostation:monoplot
 ***************************************************************************/
#include "monoplotalgorithm.h"

#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsgeometry.h>
#include <qgslinestring.h>
#include <qgspoint.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsprocessingutils.h>
#include <qgsrasterlayer.h>

#include "dem/demcoverage.h"
#include "dem/demintersection.h"
#include "dem/monoplotter.h"
#include "geometrymonoplotter.h"
#include "processingblock.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

QString MonoplotAlgorithm::name() const
{
  return QStringLiteral( "monoplot" );
}

QString MonoplotAlgorithm::displayName() const
{
  return QObject::tr( "Monoplot image features onto a DEM" );
}

QStringList MonoplotAlgorithm::tags() const
{
  return QObject::tr( "photogrammetry,monoplotting,dem,terrain,map revision,digitise,oblique" ).split( ',' );
}

QString MonoplotAlgorithm::group() const
{
  return QObject::tr( "Monoplotting" );
}

QString MonoplotAlgorithm::groupId() const
{
  return QStringLiteral( "monoplotting" );
}

QString MonoplotAlgorithm::helpText() const
{
  return QObject::tr( "Turns features digitised on one oriented image into map features with heights: every vertex's "
                      "viewing ray is intersected with the DEM (the first crossing, exact on the DEM's bilinear surface).\n\n"
                      "INPUT is an image-space layer (x = col, y = -row, no CRS), e.g. digitised over the raw image in QGIS. "
                      "Lines and polygon rings are densified so that no image segment exceeds DENSIFY_PX pixels, so they "
                      "drape over the terrain. The DEM may be in any CRS; it is read in tiles, and small nodata holes are "
                      "filled from their neighbours. BRIDGE_HOLES bridges larger holes, up to that many cells across, by "
                      "linear interpolation between their rims along rows and columns; a vertex on bridged cells gets their "
                      "height sigma (5 cm per metre from the rim, and half the rows' and columns' disagreement) in its "
                      "precision, and n_bridged counts such vertices.\n\n"
                      "The output is in the block CRS with Z; input attributes are kept, and sigma_x, sigma_y, sigma_z "
                      "(metres, worst vertex) propagate PIXEL_SIGMA_PX, DEM_SIGMA_M and the image's exterior-orientation "
                      "sigmas: grazing rays far from the camera are weak, and the numbers show it.\n\n"
                      "Every feature gets a status: ok, or why it cannot be monoplotted - outside_image (a vertex outside "
                      "the frame), misses_dem (a ray above the horizon or past the DEM), below_dem, dem_hole (a nodata hole "
                      "too large to fill), no_geometry (the input feature has none) - with the sentence in message; such a "
                      "feature keeps its attributes without geometry (NULL: no coordinate is written for it, never NaN). A line (not a polygon) that meets a hole or the horizon part-way keeps its longest resolved "
                      "part, with the status saying why it was cut (CUT_COUNT counts them). The run fails only when no "
                      "feature can be monoplotted." );
}

MonoplotAlgorithm *MonoplotAlgorithm::createInstance() const
{
  return new MonoplotAlgorithm();
}

void MonoplotAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "IMAGE" ), QObject::tr( "Image id" ) ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "DEM" ) ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "INPUT" ), QObject::tr( "Features digitised on the image (pixel space)" ),
                QList<int>() << QgsProcessing::TypeVectorAnyGeometry ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "DENSIFY_PX" ), QObject::tr( "Densify lines every (pixels)" ), QgsProcessingParameterNumber::Double, 5.0, false, 0.1 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "PIXEL_SIGMA_PX" ), QObject::tr( "Digitising precision (pixels)" ), QgsProcessingParameterNumber::Double, 0.5, false, 0.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "DEM_SIGMA_M" ), QObject::tr( "DEM height precision (m)" ), QgsProcessingParameterNumber::Double, 0.0, false, 0.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "BRIDGE_HOLES" ), QObject::tr( "Bridge nodata holes up to (cells across; 0: only the small ones are filled)" ),
                QgsProcessingParameterNumber::Integer, 0, true, 0, 4096 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Monoplotted features" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "FILLED_DEM_CELLS" ), QObject::tr( "DEM cells filled in holes" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "BRIDGED_DEM_CELLS" ), QObject::tr( "DEM cells bridged in larger holes" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "BRIDGED_VERTICES" ), QObject::tr( "Vertices on bridged DEM cells" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "MONOPLOTTED_COUNT" ), QObject::tr( "Features monoplotted" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "FAILED_COUNT" ), QObject::tr( "Features that cannot be monoplotted" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "CUT_COUNT" ), QObject::tr( "Lines kept in part (their longest resolved part)" ) ) );
}

QVariantMap MonoplotAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QString imageId = parameterAsString( parameters, QStringLiteral( "IMAGE" ), context ).trimmed();
  const geostation::BlockImage &blockImage = GeoStationProcessing::blockImage( block, imageId );
  const geostation::OrientedImage image = GeoStationProcessing::orientedImage( block, blockImage );
  const QgsCoordinateReferenceSystem crs = GeoStationProcessing::blockCrs( block );

  QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context );
  if ( !demLayer )
    throw QgsProcessingException( invalidRasterError( parameters, QStringLiteral( "DEM" ) ) );
  std::unique_ptr<geostation::Dem> dem;
  std::unique_ptr<geostation::CrsTransform> blockToDem;
  geostation::DemOptions demOptions;
  if ( parameters.value( QStringLiteral( "BRIDGE_HOLES" ) ).isValid() )
    demOptions.bridgeHolesUpToCells = parameterAsInt( parameters, QStringLiteral( "BRIDGE_HOLES" ), context );
  GeoStationProcessing::LoadedDem loaded = GeoStationProcessing::loadDem( demLayer->source(), block, demOptions );
  dem = std::move( loaded.dem );
  blockToDem = std::move( loaded.blockToDem );

  std::unique_ptr<QgsProcessingFeatureSource> source( parameterAsSource( parameters, QStringLiteral( "INPUT" ), context ) );
  if ( !source )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "INPUT" ) ) );
  const QgsCoordinateReferenceSystem inputCrs = source->sourceCrs();
  if ( inputCrs.isValid() && !inputCrs.description().startsWith( QLatin1String( "Undefined" ) ) && !inputCrs.authid().isEmpty() )
    throw QgsProcessingException( QObject::tr( "INPUT is in %1, not in image pixel space; digitise on the raw image (x = col, y = -row, no CRS)." ).arg( inputCrs.userFriendlyIdentifier() ) );

  geostation::MonoplotOptions options;
  options.pixelSigmaPx = parameterAsDouble( parameters, QStringLiteral( "PIXEL_SIGMA_PX" ), context );
  options.demSigmaM = parameterAsDouble( parameters, QStringLiteral( "DEM_SIGMA_M" ), context );
  const geostation::Monoplotter monoplotter( image, *dem, *blockToDem, options );

  // The DEM must lie under the image: some of its rays towards the ground must meet it (core's coverage of the
  // frame, as the orientation dock shows it; a scanned film's frame through its scan affine)
  const geostation::Camera &camera = image.camera();
  const geostation::DemCoverageSummary coverage = geostation::demCoverageOfImage( monoplotter );
  if ( coverage.onDem == 0 )
    throw QgsProcessingException( QObject::tr( "The DEM does not cover the footprint of image %1: no viewing ray of the image meets it." ).arg( imageId ) );
  if ( !coverage.complete() )
    feedback->pushInfo( QString::fromStdString( coverage.message ) ); // the features it leaves without a height are warned of one by one

  GeoStationProcessing::GeometryMonoplotter mono { monoplotter, parameterAsDouble( parameters, QStringLiteral( "DENSIFY_PX" ), context ), camera.width, camera.height };
  QgsFields newFields;
  for ( const char *name : { "sigma_x", "sigma_y", "sigma_z" } )
    newFields.append( QgsField( QString::fromLatin1( name ), QVariant::Double ) );
  newFields.append( QgsField( QStringLiteral( "n_vertices" ), QVariant::Int ) );
  newFields.append( QgsField( QStringLiteral( "n_bridged" ), QVariant::Int ) );
  newFields.append( QgsField( QLatin1String( fs::kMethod ), QVariant::String ) );
  newFields.append( QgsField( QLatin1String( fs::kStatus ), QVariant::String ) );
  newFields.append( QgsField( QLatin1String( fs::kMessage ), QVariant::String ) );
  const QgsFields fields = QgsProcessingUtils::combineFields( source->fields(), newFields );

  // Everything is computed before the output is created. A feature that cannot be monoplotted (a ray into a
  // large DEM hole, above the horizon, a vertex outside the frame) is kept with an empty geometry and its
  // status; the run fails only when no feature at all can be monoplotted, and then leaves no file.
  QVector<QgsFeature> features;
  StatusTally statusCounts;
  long resolved = 0, failed = 0, cut = 0, bridgedVertices = 0;
  QString firstProblem;
  constexpr int kWarningsShown = 20;
  const double step = source->featureCount() > 0 ? 90.0 / source->featureCount() : 0.0;
  QgsFeatureIterator it = source->getFeatures();
  QgsFeature f;
  while ( it.nextFeature( f ) )
  {
    if ( feedback->isCanceled() )
      return QVariantMap();
    QgsFeature out( fields );
    QgsAttributes attributes = f.attributes();
    mono.reset( QObject::tr( "its geometry cannot be monoplotted" ), QStringLiteral( "no_solution" ) );
    QString status = QStringLiteral( "ok" ), message;
    if ( !f.hasGeometry() || f.geometry().isEmpty() )
    {
      // nothing to monoplot: its row is kept, and says so
      status = QStringLiteral( "no_geometry" );
      message = QObject::tr( "Feature %1 has no geometry in the image." ).arg( f.id() );
      if ( firstProblem.isEmpty() )
        firstProblem = message;
      if ( ++failed + cut <= kWarningsShown )
        feedback->pushWarning( message );
    }
    else
    {
      if ( std::unique_ptr<QgsAbstractGeometry> g = mono.geometry( f.geometry().constGet() ) )
      {
        out.setGeometry( QgsGeometry( std::move( g ) ) );
        ++resolved;
        if ( mono.cutVertices > 0 )
        {
          status = mono.status;
          message = QObject::tr( "Feature %1 is monoplotted in part: %2; its longest resolved part is kept (%3 of %4 densified vertices cut away)." )
                    .arg( f.id() ).arg( mono.problem ).arg( mono.cutVertices ).arg( mono.vertices + mono.cutVertices );
          if ( ++cut + failed <= kWarningsShown )
            feedback->pushWarning( message );
        }
      }
      else
      {
        status = mono.status;
        message = QObject::tr( "Feature %1 cannot be monoplotted: %2" ).arg( f.id() ).arg( mono.problem );
        if ( firstProblem.isEmpty() )
          firstProblem = message;
        if ( ++failed + cut <= kWarningsShown )
          feedback->pushWarning( message );
      }
    }
    statusCounts.add( status );
    const bool ok = out.hasGeometry(); // monoplotted, perhaps in part
    const QVariant none;
    attributes << ( ok ? QVariant( mono.worst.x() ) : none ) << ( ok ? QVariant( mono.worst.y() ) : none ) << ( ok ? QVariant( mono.worst.z() ) : none )
               << mono.vertices << ( ok ? QVariant( mono.bridged ) : none ) << QStringLiteral( "monoplot-DEM" ) << status << ( message.isEmpty() ? none : QVariant( message ) );
    bridgedVertices += ok ? mono.bridged : 0;
    out.setAttributes( attributes );
    features << out;
    feedback->setProgress( step * features.size() );
  }

  if ( failed > 0 && resolved == 0 )
    throw QgsProcessingException( failed == 1 ? firstProblem : QObject::tr( "None of the %1 features can be monoplotted; the first: %2" ).arg( failed ).arg( firstProblem ) );
  if ( failed + cut > kWarningsShown )
    feedback->pushWarning( QObject::tr( "… and %1 more features that cannot be monoplotted, or only in part (see their status and message)." ).arg( failed + cut - kWarningsShown ) );
  feedback->pushInfo( QObject::tr( "%1 of %2 features monoplotted (%3)." ).arg( resolved ).arg( features.size() ).arg( statusCounts.text() ) );

  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::addZ( source->wkbType() ), crs );
  for ( QgsFeature &out : features )
    sink.add( out );
  sink.close( true ); // an unresolved feature: its row and status, no NaN
  feedback->setProgress( 100 );
  if ( dem->filledCellCount() > 0 )
    feedback->pushInfo( QObject::tr( "%1 DEM cells in nodata holes were filled from their neighbours." ).arg( dem->filledCellCount() ) );
  if ( dem->bridgedCellCount() > 0 )
    feedback->pushInfo( QObject::tr( "%1 DEM cells in larger holes were bridged; %2 vertices lie on them, with the bridge's height sigma in their precision." )
                        .arg( dem->bridgedCellCount() ).arg( bridgedVertices ) );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), sink.destination() );
  outputs.insert( QStringLiteral( "FILLED_DEM_CELLS" ), static_cast<double>( dem->filledCellCount() ) );
  outputs.insert( QStringLiteral( "BRIDGED_DEM_CELLS" ), static_cast<double>( dem->bridgedCellCount() ) );
  outputs.insert( QStringLiteral( "BRIDGED_VERTICES" ), static_cast<double>( bridgedVertices ) );
  outputs.insert( QStringLiteral( "MONOPLOTTED_COUNT" ), static_cast<double>( resolved ) );
  outputs.insert( QStringLiteral( "FAILED_COUNT" ), static_cast<double>( failed ) );
  outputs.insert( QStringLiteral( "CUT_COUNT" ), static_cast<double>( cut ) );
  return outputs;
}

} // namespace GeoStationProcessing
