/***************************************************************************
  simulatesurveyalgorithm.cpp - geostation:simulate_survey
  -------------------------------------------------------------------------
  The survey simulator (core/simulation) as a Processing algorithm: the
  same options as the geostation-simulate command line.
 ***************************************************************************/
#include "simulatesurveyalgorithm.h"
#include "processingblock.h"

#include <QDir>

#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsproviderregistry.h>
#include <qgsrasterlayer.h>
#include <qgsvectorlayer.h>

#include "simulation/surveysimulator.h"

namespace GeoStationProcessing
{

namespace
{
  //! "path|layername=x" for OGR: the file and the layer, as the core reads them.
  std::string ogrSource( const QgsVectorLayer *layer )
  {
    const QVariantMap parts = QgsProviderRegistry::instance()->decodeUri( layer->providerType(), layer->source() );
    QString source = parts.value( QStringLiteral( "path" ) ).toString();
    if ( source.isEmpty() )
      source = layer->source();
    const QString layerName = parts.value( QStringLiteral( "layerName" ) ).toString();
    if ( !layerName.isEmpty() )
      source += QStringLiteral( "|layername=" ) + layerName;
    return source.toStdString();
  }

  void addAdvanced( QgsProcessingAlgorithm *algorithm, QgsProcessingParameterDefinition *parameter, QList<QgsProcessingParameterDefinition *> &list )
  {
    parameter->setFlags( parameter->flags() | QgsProcessingParameterDefinition::FlagAdvanced );
    list << parameter;
    (void)algorithm;
  }
}

QString SimulateSurveyAlgorithm::name() const
{
  return QStringLiteral( "simulate_survey" );
}

QString SimulateSurveyAlgorithm::displayName() const
{
  return QObject::tr( "Simulate a survey" );
}

QStringList SimulateSurveyAlgorithm::tags() const
{
  return QObject::tr( "simulation,synthetic,test data,ground truth,mobile mapping,van,aerial,stereo,oblique,render" ).split( ',' );
}

QString SimulateSurveyAlgorithm::group() const
{
  return QObject::tr( "Simulation" );
}

QString SimulateSurveyAlgorithm::groupId() const
{
  return QStringLiteral( "simulation" );
}

QString SimulateSurveyAlgorithm::helpText() const
{
  return QObject::tr( "Renders a synthetic survey whose truth is known exactly, for testing measurements and training.\n\n"
                      "PRESET highway: a mapping van with 2-6 roof cameras driving along a road (stations every SPACING m); "
                      "aerial_stereo: a strip of frame images with 60 % forward overlap at GSD metres per pixel; "
                      "oblique_photo: one oblique photo over hilly terrain, for monoplotting.\n\n"
                      "Terrain comes from DEM (any CRS, nodata filled) or is procedural; roads from ROADS (reprojected "
                      "to the block CRS) or procedural, with markings, kerbs, poles, signs, hydrants, manholes, trees, "
                      "parked cars, shadows and signalised control targets. ORTHO drapes an orthophoto as ground texture.\n\n"
                      "OUTPUT_DIR receives block.geostation.json (orientation with GNSS/INS errors), truth.geostation.json "
                      "(exact), images/, terrain.tif, simulation.json and truth.gpkg (layers objects, roads, control, "
                      "occluders and the table image_truth with the true pixel of every visible truth point). "
                      "The same SEED gives the same output. Degradations (noise, blur, vignetting, exposure, bit errors, "
                      "JPEG) are off unless set." );
}

SimulateSurveyAlgorithm *SimulateSurveyAlgorithm::createInstance() const
{
  return new SimulateSurveyAlgorithm();
}

void SimulateSurveyAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "PRESET" ), QObject::tr( "Preset" ),
                QStringList { QStringLiteral( "highway" ), QStringLiteral( "aerial_stereo" ), QStringLiteral( "oblique_photo" ) }, false,
                QStringLiteral( "highway" ), false, true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "SEED" ), QObject::tr( "Random seed" ), QgsProcessingParameterNumber::Integer, 1, false, 0 ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "Terrain (DEM)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterVectorLayer( QStringLiteral( "ROADS" ), QObject::tr( "Road centre lines" ),
                QList<int>() << QgsProcessing::TypeVectorLine, QVariant(), true ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "ORTHO" ), QObject::tr( "Orthophoto draped as ground texture" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "STATIONS" ), QObject::tr( "Stations (0: the preset's default)" ), QgsProcessingParameterNumber::Integer, 0, true, 0, 2000 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "IMAGE_WIDTH" ), QObject::tr( "Image width (0: the preset's default)" ), QgsProcessingParameterNumber::Integer, 0, true, 0, 8000 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "IMAGE_HEIGHT" ), QObject::tr( "Image height (0: the preset's default)" ), QgsProcessingParameterNumber::Integer, 0, true, 0, 8000 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "NOISE" ), QObject::tr( "Image noise (grey levels)" ), QgsProcessingParameterNumber::Double, 0.0, true, 0.0, 128.0 ) );
  QList<QgsProcessingParameterDefinition *> advanced;
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "CAMERAS" ), QObject::tr( "highway: cameras on the van" ), QgsProcessingParameterNumber::Integer, 3, true, 2, 6 ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "SPACING" ), QObject::tr( "highway: station spacing (m)" ), QgsProcessingParameterNumber::Double, 5.0, true, 1.0, 100.0 ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "GSD" ), QObject::tr( "aerial_stereo: ground pixel size (m)" ), QgsProcessingParameterNumber::Double, 0.10, true, 0.01, 5.0 ), advanced );
  addAdvanced( this, new QgsProcessingParameterBoolean( QStringLiteral( "SCANNED_FILM" ), QObject::tr( "oblique_photo: scanned film with fiducial marks" ), false, true ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "BLUR" ), QObject::tr( "Blur (Gaussian sigma, px)" ), QgsProcessingParameterNumber::Double, 0.0, true, 0.0, 50.0 ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "VIGNETTING" ), QObject::tr( "Vignetting (fall-off at the corners, 0-1)" ), QgsProcessingParameterNumber::Double, 0.0, true, 0.0, 1.0 ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "EXPOSURE" ), QObject::tr( "Exposure gain (<1 under, >1 over)" ), QgsProcessingParameterNumber::Double, 1.0, true, 0.01, 20.0 ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "BIT_ERRORS" ), QObject::tr( "Bit errors (fraction of pixels)" ), QgsProcessingParameterNumber::Double, 0.0, true, 0.0, 0.5 ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "JPEG_QUALITY" ), QObject::tr( "JPEG quality (0: no JPEG)" ), QgsProcessingParameterNumber::Integer, 0, true, 0, 100 ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "POSE_NOISE_SCALE" ), QObject::tr( "GNSS/INS error scale (0: block = truth)" ), QgsProcessingParameterNumber::Double, 1.0, true, 0.0, 100.0 ), advanced );
  addAdvanced( this, new QgsProcessingParameterNumber( QStringLiteral( "SUPERSAMPLING" ), QObject::tr( "Anti-aliasing samples per edge pixel side" ), QgsProcessingParameterNumber::Integer, 3, true, 1, 16 ), advanced );
  for ( QgsProcessingParameterDefinition *parameter : advanced )
    addParameter( parameter );
  addParameter( new QgsProcessingParameterFolderDestination( QStringLiteral( "OUTPUT_DIR" ), QObject::tr( "Output folder" ) ) );
  addOutput( new QgsProcessingOutputFile( QStringLiteral( "BLOCK" ), QObject::tr( "Block (with GNSS/INS errors)" ) ) );
  addOutput( new QgsProcessingOutputFile( QStringLiteral( "TRUTH_BLOCK" ), QObject::tr( "Exact block" ) ) );
  addOutput( new QgsProcessingOutputFile( QStringLiteral( "TRUTH" ), QObject::tr( "Truth GeoPackage" ) ) );
  addOutput( new QgsProcessingOutputRasterLayer( QStringLiteral( "TERRAIN" ), QObject::tr( "Terrain" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "IMAGES" ), QObject::tr( "Images rendered" ) ) );
}

QVariantMap SimulateSurveyAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  geostation::SimulationOptions options;
  options.preset = geostation::surveyPresetFromName( parameterAsEnumString( parameters, QStringLiteral( "PRESET" ), context ).toStdString() );
  options.seed = static_cast<uint32_t>( parameterAsInt( parameters, QStringLiteral( "SEED" ), context ) );
  options.outputDir = parameterAsString( parameters, QStringLiteral( "OUTPUT_DIR" ), context ).toStdString();
  if ( QgsRasterLayer *dem = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
    options.demPath = dem->source().toStdString();
  if ( QgsVectorLayer *roads = parameterAsVectorLayer( parameters, QStringLiteral( "ROADS" ), context ) )
    options.roadsPath = ogrSource( roads );
  if ( QgsRasterLayer *ortho = parameterAsRasterLayer( parameters, QStringLiteral( "ORTHO" ), context ) )
    options.orthoPath = ortho->source().toStdString();
  const auto number = [&]( const char *name, double fallback )
  {
    const QVariant v = parameters.value( QString::fromLatin1( name ) );
    return v.isValid() && !v.isNull() && !v.toString().isEmpty() ? parameterAsDouble( parameters, QString::fromLatin1( name ), context ) : fallback;
  };
  options.stations = static_cast<int>( number( "STATIONS", 0 ) );
  options.imageWidth = static_cast<int>( number( "IMAGE_WIDTH", 0 ) );
  options.imageHeight = static_cast<int>( number( "IMAGE_HEIGHT", 0 ) );
  options.degradation.noiseSigma = number( "NOISE", 0.0 );
  options.cameras = static_cast<int>( number( "CAMERAS", 3 ) );
  options.stationSpacingM = number( "SPACING", 5.0 );
  options.groundPixelSizeM = number( "GSD", 0.10 );
  options.degradation.blurSigmaPx = number( "BLUR", 0.0 );
  options.degradation.vignetting = number( "VIGNETTING", 0.0 );
  options.degradation.exposure = number( "EXPOSURE", 1.0 );
  options.degradation.bitErrorRate = number( "BIT_ERRORS", 0.0 );
  options.degradation.jpegQuality = static_cast<int>( number( "JPEG_QUALITY", 0 ) );
  options.poseNoiseScale = number( "POSE_NOISE_SCALE", 1.0 );
  options.supersampling = static_cast<int>( number( "SUPERSAMPLING", 3 ) );
  options.scannedFilm = parameterAsBool( parameters, QStringLiteral( "SCANNED_FILM" ), context );
  options.progress = GeoStationProcessing::progressOf( feedback );

  geostation::SimulationSummary summary;
  try
  {
    summary = geostation::simulateSurvey( options );
  }
  catch ( const geostation::SimulationCancelled & )
  {
    throw QgsProcessingException( QObject::tr( "The simulation was cancelled; the output folder is unchanged." ) );
  }
  catch ( const std::exception &e )
  {
    throw QgsProcessingException( QString::fromStdString( e.what() ) );
  }
  for ( const std::string &note : summary.notes )
    feedback->pushInfo( QString::fromStdString( note ) );
  feedback->pushInfo( QObject::tr( "%1 images of %2 stations; rendered %3 Mpx in %4 s; truth: %5 objects, %6 control points, %7 road lines, %8 image observations." )
                      .arg( summary.images ).arg( summary.stations ).arg( summary.pixels / 1e6, 0, 'f', 1 ).arg( summary.renderSeconds, 0, 'f', 1 )
                      .arg( summary.objects ).arg( summary.controlPoints ).arg( summary.roadLines ).arg( summary.imageTruthRows ) );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT_DIR" ), QString::fromStdString( options.outputDir.string() ) );
  outputs.insert( QStringLiteral( "BLOCK" ), QString::fromStdString( summary.blockFile.string() ) );
  outputs.insert( QStringLiteral( "TRUTH_BLOCK" ), QString::fromStdString( summary.truthBlockFile.string() ) );
  outputs.insert( QStringLiteral( "TRUTH" ), QString::fromStdString( summary.truthGeoPackage.string() ) );
  outputs.insert( QStringLiteral( "TERRAIN" ), QString::fromStdString( summary.terrainFile.string() ) );
  outputs.insert( QStringLiteral( "IMAGES" ), summary.images );
  return outputs;
}

} // namespace GeoStationProcessing
