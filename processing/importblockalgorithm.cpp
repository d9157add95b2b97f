/***************************************************************************
  importblockalgorithm.cpp - geostation:import_block
 ***************************************************************************/
#include "importblockalgorithm.h"

#include <memory>

#include <QFile>
#include <QFileInfo>

#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>

#include "io/colmapimport.h"
#include "io/metashapeimport.h"
#include "io/opencvcalibration.h"
#include "io/trajectoryimport.h"
#include "io/textfile.h"
#include "processingblock.h"
#include "processingtables.h"

namespace GeoStationProcessing
{

namespace
{
  const QStringList sFormats { QStringLiteral( "auto" ), QStringLiteral( "colmap" ), QStringLiteral( "metashape" ), QStringLiteral( "opencv_trajectory" ) };
  const QStringList sAngleUnits { QStringLiteral( "degrees" ), QStringLiteral( "radians" ) };

  /**
   * INPUT: a file or a folder. A COLMAP model is a folder, which
   * QgsProcessingParameterFile in file mode refuses; any existing path is
   * accepted here and processAlgorithm() says what it is not.
   */
  class ModelPathParameter : public QgsProcessingParameterFile
  {
    public:
      ModelPathParameter( const QString &name, const QString &description )
        : QgsProcessingParameterFile( name, description ) {}

      QgsProcessingParameterDefinition *clone() const override { return new ModelPathParameter( *this ); }

      bool checkValueIsAcceptable( const QVariant &input, QgsProcessingContext * = nullptr ) const override
      {
        return input.isValid() && !input.toString().trimmed().isEmpty();
      }
  };
} // namespace

QString ImportBlockAlgorithm::name() const { return QStringLiteral( "import_block" ); }
QString ImportBlockAlgorithm::displayName() const { return QObject::tr( "Import block (COLMAP, Metashape, calibration + trajectory)" ); }
QStringList ImportBlockAlgorithm::tags() const { return QObject::tr( "photogrammetry,import,colmap,structure from motion,sfm,block,orientation,georeference,opencv,calibration,trajectory,gnss,ins,mobile mapping" ).split( ',' ); }
QString ImportBlockAlgorithm::group() const { return QObject::tr( "Block" ); }
QString ImportBlockAlgorithm::groupId() const { return QStringLiteral( "block" ); }

QString ImportBlockAlgorithm::helpText() const
{
  return QObject::tr( "Turns a COLMAP sparse model, Metashape's camera XML, or a mapping van's OpenCV calibration with "
                      "its trajectory, into a GeoStation block.\n\n"
                      "COLMAP: INPUT is the model folder (cameras, images and points3D, text or binary) or any of its files.\n\n"
                      "Cameras SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV and FULL_OPENCV (without k4-k6) "
                      "convert exactly; other models are refused by name and their images left out, as the report says. "
                      "Every registered image becomes an oriented image; the images of one COLMAP frame (COLMAP 3.12 and "
                      "later: a rig's exposure) become one station, named after the reference camera's image, and without "
                      "frames every image is its own station.\n\n"
                      "IMAGES is the folder COLMAP's image names are relative to (default: beside the model or an "
                      "\"images\" folder above it); every image must be there, readable and of its camera's size.\n\n"
                      "CRS is the block's CRS (projected, or a local engineering CRS, in metres). GEOREFERENCE brings "
                      "a model in COLMAP's arbitrary frame into it by a similarity transform: a table image, X, Y, Z "
                      "(known camera centres by COLMAP's image NAME) or point_id, X, Y, Z (control points by COLMAP's "
                      "POINT3D_ID). The report lists the transform and the residual of every known position.\n\n"
                      "OUTPUT_OBSERVATIONS (point_id, image_id, col, row) and OUTPUT_POINTS (point_id, X, Y, Z, error_px) "
                      "are the model's 3-D points as tie points, ready for bundle_adjust and intersect.\n\n"
                      "Metashape: INPUT is the XML of File > Export > Export Cameras. Frame sensors convert exactly (Metashape's "
                      "P1, P2 are OpenCV's p2, p1; fx = f + b1); k4, p3, p4, skew b2 and other sensor types are refused by name. "
                      "A referenced chunk's cameras are brought from geocentric coordinates into CRS; images are found by "
                      "label in IMAGES (default: beside the XML). Markers with reference coordinates become control points "
                      "(check points where the reference is not enabled), brought from the chunk's reference CRS into CRS: "
                      "OUTPUT_CONTROL (point_id, X, Y, Z, sx, sy, sz, role) is bundle_adjust's GCPS table, and their pinned "
                      "projections go into OUTPUT_OBSERVATIONS.\n\n"
                      "Calibration + trajectory: INPUT is an OpenCV calibration (YAML or XML: camera_matrix, "
                      "distortion_coefficients, image_width, image_height; or a sequence \"cameras\" whose entries also "
                      "have id, lever_arm [x, y, z] m in the body frame x forward, y right, z down, boresight [roll, pitch, "
                      "heading] deg and image_pattern such as images/{station}_front.jpg). TRAJECTORY is a CSV with one row "
                      "per station: time, station, X, Y, Z (block CRS) or latitude, longitude, height (WGS 84), and "
                      "roll, pitch, heading (the vehicle, heading from true north) or omega, phi, kappa (one camera's own "
                      "orientation), plus image or image_CAMERA columns (CAMERA: a camera's id) where there is no pattern. ANGLES says "
                      "whether the table's angles are degrees (default) or radians; radians read as degrees are refused.\n\n"
                      "A high-rate GNSS/INS trajectory (rows at its own times, a time column) with EVENTS, a CSV of the "
                      "exposures (time on the trajectory's clock, station, image or image_CAMERA columns or the "
                      "patterns): each event becomes a station whose pose is interpolated at its time (positions by cubic "
                      "Hermite curves, attitudes by slerp). Events outside the trajectory or in a gap longer than MAX_GAP_S "
                      "are left out and listed in the report." );
}

ImportBlockAlgorithm *ImportBlockAlgorithm::createInstance() const { return new ImportBlockAlgorithm(); }

void ImportBlockAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( new ModelPathParameter( QStringLiteral( "INPUT" ), QObject::tr( "Model: COLMAP folder (or one of its files), Metashape cameras XML or OpenCV calibration" ) ) );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "FORMAT" ), QObject::tr( "Format" ), sFormats, false, QStringLiteral( "auto" ), false, true ) );
  addParameter( new QgsProcessingParameterFile( QStringLiteral( "TRAJECTORY" ), QObject::tr( "Trajectory table (calibration + trajectory)" ), QgsProcessingParameterFile::File,
                QString(), QVariant(), true, QObject::tr( "CSV (*.csv *.txt)" ) ) );
  addParameter( new QgsProcessingParameterFile( QStringLiteral( "EVENTS" ), QObject::tr( "Exposure events (time, image names) to interpolate in the trajectory" ),
                QgsProcessingParameterFile::File, QString(), QVariant(), true, QObject::tr( "CSV (*.csv *.txt)" ) ) );
  auto maxGap = std::make_unique<QgsProcessingParameterNumber>( QStringLiteral( "MAX_GAP_S" ), QObject::tr( "Largest trajectory gap to interpolate across (s)" ),
                                                                QgsProcessingParameterNumber::Double, 1.0, false, 1e-3, 3600.0 );
  maxGap->setFlags( maxGap->flags() | QgsProcessingParameterDefinition::FlagAdvanced );
  addParameter( maxGap.release() );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "ANGLES" ), QObject::tr( "Angles of the trajectory table" ), sAngleUnits, false, QStringLiteral( "degrees" ), false, true ) );
  addParameter( new QgsProcessingParameterFile( QStringLiteral( "IMAGES" ), QObject::tr( "Image folder" ), QgsProcessingParameterFile::Folder, QString(), QVariant(), true ) );
  addParameter( new QgsProcessingParameterCrs( QStringLiteral( "CRS" ), QObject::tr( "Block CRS" ) ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "GEOREFERENCE" ), QObject::tr( "Known camera centres (image, X, Y, Z) or control points (point_id, X, Y, Z)" ),
                QList<int>() << QgsProcessing::TypeVector, QVariant(), true ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "OUTPUT_BLOCK" ), QObject::tr( "Block" ), QObject::tr( "GeoStation block (*.geostation.json)" ) ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "OUTPUT_OBSERVATIONS" ), QObject::tr( "Image observations of tie and control points" ), QObject::tr( "CSV (*.csv)" ), QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "OUTPUT_POINTS" ), QObject::tr( "Tie points" ), QObject::tr( "CSV (*.csv)" ), QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "OUTPUT_CONTROL" ), QObject::tr( "Control and check points (Metashape markers)" ), QObject::tr( "CSV (*.csv)" ), QVariant(), true, false ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "IMAGES_IMPORTED" ), QObject::tr( "Images imported" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "CONTROL_POINTS" ), QObject::tr( "Control and check points imported" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "GEOREFERENCE_RMS_M" ), QObject::tr( "Georeference RMS residual (m)" ) ) );
}

QVariantMap ImportBlockAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const QString input = parameterAsString( parameters, QStringLiteral( "INPUT" ), context ).trimmed();
  if ( input.isEmpty() )
    throw QgsProcessingException( QObject::tr( "INPUT: give the COLMAP model folder (or one of its files)." ) );
  QString format = parameterAsEnumString( parameters, QStringLiteral( "FORMAT" ), context );
  if ( format == QLatin1String( "auto" ) )
  {
    if ( geostation::ColmapModel::isModel( input.toStdString() ) )
      format = QStringLiteral( "colmap" );
    else if ( geostation::isMetashapeCameras( input.toStdString() ) )
      format = QStringLiteral( "metashape" );
    else if ( geostation::isOpenCvCalibration( input.toStdString() ) )
      format = QStringLiteral( "opencv_trajectory" );
    else
      throw QgsProcessingException( QObject::tr( "%1 is not a model GeoStation can import: a COLMAP model folder holds cameras.txt and images.txt "
                                                 "(or cameras.bin and images.bin), Metashape's camera XML has a <chunk> with <sensors> and <cameras>, an OpenCV "
                                                 "calibration is a YAML or XML file with camera_matrix." ).arg( input ) );
  }
  const QString trajectory = parameterAsFile( parameters, QStringLiteral( "TRAJECTORY" ), context );
  if ( format == QLatin1String( "opencv_trajectory" ) && trajectory.isEmpty() )
    throw QgsProcessingException( QObject::tr( "TRAJECTORY: a calibration needs its trajectory table (one row per station)." ) );
  const QgsCoordinateReferenceSystem crs = parameterAsCrs( parameters, QStringLiteral( "CRS" ), context );
  if ( !crs.isValid() )
    throw QgsProcessingException( QObject::tr( "CRS: give the CRS the block is to be in (projected, or a local engineering CRS, in metres)." ) );

  const std::string blockCrs = blockCrsDefinition( crs );
  const std::string imageFolder = parameterAsFile( parameters, QStringLiteral( "IMAGES" ), context ).toStdString();

  geostation::KnownPositions known;
  std::unique_ptr<QgsProcessingFeatureSource> georeference( parameterAsSource( parameters, QStringLiteral( "GEOREFERENCE" ), context ) );
  if ( !georeference && parameters.value( QStringLiteral( "GEOREFERENCE" ) ).isValid() && !parameters.value( QStringLiteral( "GEOREFERENCE" ) ).toString().isEmpty() )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "GEOREFERENCE" ) ) );
  if ( georeference )
  {
    const GeoStationProcessing::KnownPositionTable table = GeoStationProcessing::readKnownPositions( georeference.get(), QObject::tr( "GEOREFERENCE" ) );
    for ( const auto &row : table.rows )
      ( table.cameraCentres ? known.cameraCentres : known.controlPoints )[row.first.toStdString()] = row.second;
  }

  geostation::BlockImportSummary import;
  if ( format == QLatin1String( "colmap" ) )
  {
    feedback->pushInfo( QObject::tr( "Reading the COLMAP model %1" ).arg( input ) );
    geostation::ColmapImportOptions options;
    options.crs = blockCrs;
    options.imageFolder = imageFolder;
    const geostation::ColmapModel model = geostation::ColmapModel::read( input.toStdString() );
    feedback->setProgress( 30 );
    import = geostation::importColmapModel( model, geostation::ColmapModel::modelFolder( input.toStdString() ), options );
  }
  else if ( format == QLatin1String( "metashape" ) )
  {
    feedback->pushInfo( QObject::tr( "Reading Metashape's cameras %1" ).arg( input ) );
    geostation::MetashapeImportOptions options;
    options.crs = blockCrs;
    options.imageFolder = imageFolder;
    import = geostation::importMetashapeCameras( input.toStdString(), options );
  }
  else
  {
    feedback->pushInfo( QObject::tr( "Reading the calibration %1 and the trajectory %2" ).arg( input, trajectory ) );
    geostation::TrajectoryImportOptions options;
    options.crs = blockCrs;
    options.imageFolder = imageFolder;
    options.anglesInRadians = parameterAsEnumString( parameters, QStringLiteral( "ANGLES" ), context ) == QLatin1String( "radians" );
    options.eventsCsv = parameterAsFile( parameters, QStringLiteral( "EVENTS" ), context ).toStdString();
    options.maxTrajectoryGapS = parameterAsDouble( parameters, QStringLiteral( "MAX_GAP_S" ), context );
    import = geostation::importTrajectory( geostation::readOpenCvCalibration( input.toStdString() ), trajectory.toStdString(), options );
  }
  feedback->setProgress( 70 );
  if ( !known.cameraCentres.empty() || !known.controlPoints.empty() )
    geostation::georeferenceImport( import, known );
  if ( feedback->isCanceled() )
    return {};
  for ( const std::string &s : import.converted )
    feedback->pushInfo( QString::fromStdString( s ) );
  for ( const std::string &s : import.dropped )
    feedback->reportError( QObject::tr( "Dropped: %1" ).arg( QString::fromStdString( s ) ) );
  for ( const std::string &s : import.warnings )
    feedback->pushWarning( QString::fromStdString( s ) );
  if ( !import.georeference )
    feedback->pushInfo( QObject::tr( "No GEOREFERENCE: the model's coordinates are taken as they are, in %1." ).arg( crs.userFriendlyIdentifier() ) );

  // tables first, then the block and its report; on any failure nothing is left behind
  const QString blockPath = parameterAsFileOutput( parameters, QStringLiteral( "OUTPUT_BLOCK" ), context );
  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  const QString observationsPath = parameterAsFileOutput( parameters, QStringLiteral( "OUTPUT_OBSERVATIONS" ), context );
  const QString pointsPath = parameterAsFileOutput( parameters, QStringLiteral( "OUTPUT_POINTS" ), context );
  const QString controlPath = parameterAsFileOutput( parameters, QStringLiteral( "OUTPUT_CONTROL" ), context );
  try
  {
    geostation::writeTiePointTables( import, observationsPath.toStdString(), pointsPath.toStdString() );
    if ( !controlPath.isEmpty() )
      geostation::writeControlTable( import, controlPath.toStdString() );
    if ( !reportPath.isEmpty() )
      geostation::writeTextFileAtomically( reportPath.toStdString(), geostation::importReportJsonText( import ) );
    import.block.save( blockPath.toStdString() );
  }
  catch ( const std::exception &e )
  {
    removeIfWritten( observationsPath );
    removeIfWritten( pointsPath );
    removeIfWritten( controlPath );
    removeIfWritten( reportPath );
    throw QgsProcessingException( QString::fromStdString( e.what() ) );
  }
  feedback->setProgress( 100 );
  feedback->pushInfo( QObject::tr( "%n image(s) imported", nullptr, static_cast<int>( import.block.images.size() ) ) );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT_BLOCK" ), blockPath );
  outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  outputs.insert( QStringLiteral( "OUTPUT_OBSERVATIONS" ), observationsPath );
  outputs.insert( QStringLiteral( "OUTPUT_POINTS" ), pointsPath );
  outputs.insert( QStringLiteral( "OUTPUT_CONTROL" ), controlPath );
  outputs.insert( QStringLiteral( "CONTROL_POINTS" ), static_cast<int>( import.controlPoints.size() ) );
  outputs.insert( QStringLiteral( "IMAGES_IMPORTED" ), static_cast<int>( import.block.images.size() ) );
  outputs.insert( QStringLiteral( "GEOREFERENCE_RMS_M" ), import.georeference ? QVariant( import.georeference->rmsM ) : QVariant() );
  return outputs;
}

} // namespace GeoStationProcessing
