/***************************************************************************
  extractroadsalgorithm.cpp - geostation:extract_roads
  -------------------------------------------------------------------------
  A stereo pair in, its road network out (core/extraction): lines found in
  one image and verified in the other, alternately, as image-space lines
  of both images, 3-D lines with sigmas for an oriented pair, the open
  ends, and a JSON report of the rounds. Everything is computed before
  any output is created; a pair without roads gives empty layers and a
  report that says so.
 ***************************************************************************/
#include "extractroadsalgorithm.h"

#include <memory>
#include <optional>

#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsgeometry.h>
#include <qgslinestring.h>
#include <qgspoint.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsrasterlayer.h>

#include "dem/demintersection.h"
#include "extraction/roadnetworkextractor.h"
#include "geometry/imagespace.h"
#include "io/rasterfile.h"
#include "extractroadsreport.h"
#include "processingblock.h"
#include "processingtables.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

namespace
{
  // indices kept from before auto existed: dark 0, bright 1
  const QStringList kPolarities { QStringLiteral( "dark" ), QStringLiteral( "bright" ), QStringLiteral( "auto" ) };
  const QStringList kMappings { QStringLiteral( "multiquadric" ), QStringLiteral( "projective" ) };

  QgsGeometry imageSpaceLine( const std::vector<Eigen::Vector2d> &pixels )
  {
    QVector<double> x, y;
    for ( const Eigen::Vector2d &p : pixels )
    {
      const Eigen::Vector2d xy = geostation::imageSpaceOfPixel( p );
      x << xy.x();
      y << xy.y();
    }
    return QgsGeometry( new QgsLineString( x, y ) );
  }

  //! "right" (extracted in the left image, verified in the right), "left", or "both".
  QString acceptedIn( const std::string &symbols, bool inLeft )
  {
    const bool internal = symbols.find( 'I' ) != std::string::npos, external = symbols.find( 'E' ) != std::string::npos;
    if ( internal && external )
      return QStringLiteral( "both" );
    return ( internal == inLeft ) ? QStringLiteral( "right" ) : QStringLiteral( "left" );
  }
}

QString ExtractRoadsAlgorithm::name() const { return QStringLiteral( "extract_roads" ); }
QString ExtractRoadsAlgorithm::displayName() const { return QObject::tr( "Extract the road network of a stereo pair" ); }
QStringList ExtractRoadsAlgorithm::tags() const { return QObject::tr( "road,network,extraction,aerial,stereo,verification,3d,lines" ).split( ',' ); }
QString ExtractRoadsAlgorithm::group() const { return QObject::tr( "Image processing" ); }
QString ExtractRoadsAlgorithm::groupId() const { return QStringLiteral( "imageprocessing" ); }

QString ExtractRoadsAlgorithm::helpText() const
{
  return QObject::tr( "Extracts roads automatically from one image of a stereo pair, verifies every line in the other image, "
                      "continues from where verification stopped, alternating between the images until a round adds little, "
                      "and assembles the result into maximum-length lines between dead ends and junctions.\n\n"
                      "A road is a band with two roughly parallel borders, fairly uniform inside (centre and lane markings, "
                      "cars and shadows aside), that differs from each side by at least MIN_CONTRAST grey levels. With POLARITY "
                      "auto (the default) each side may be darker or brighter: asphalt darker than a bright field on one side and "
                      "brighter than a wood on the other (such a band must show a plateau at least 3 px wide, or every blurred "
                      "field edge would be one); dark or bright asks for roads darker or brighter than both sides.\n\n"
                      "Widths: for an oriented pair, from ROAD_WIDTH_MIN_M to ROAD_WIDTH_MAX_M on the ground (3 to 30 m by "
                      "default), divided by the ground pixel at the left image's centre, kept within 1 and 80 px: one set of "
                      "defaults serves ground pixels from 0.1 m to 10 m. ROAD_WIDTH_MIN_PX and ROAD_WIDTH_MAX_PX, when given, "
                      "are used instead (a pair registered by CONTROL has no ground pixel: 4 to 24 px unless given). A road "
                      "1 px wide is a line brighter or darker than both sides. MIN_CONTRAST, when empty, is 1.8 times the left "
                      "image's texture (the median standard deviation of 7 x 7 px windows), at least 15 grey levels: on coarse "
                      "grass, bands a little brighter or darker than their sides are everywhere.\n\n"
                      "An oriented pair is registered through its "
                      "orientation and the DEM, or a mean terrain height (MEAN_HEIGHT_M, otherwise estimated by matching); "
                      "an unoriented pair needs CONTROL (point_id, col_left, row_left, col_right, row_right) and is "
                      "registered by the MAPPING, and then only the image-space outputs are written; the verification then searches "
                      "as far either side of a mapped line as the control points' misregistration calls for. Starting points are "
                      "sought on sample lines START_SPACING_PX apart: closer lines find more of the short roads of a small image.\n\n"
                      "OUTPUT: 3-D lines in the block CRS (line_id, accepted_in, length_m, sigma_max); OUTPUT_LEFT and "
                      "OUTPUT_RIGHT: the lines in each image (x = col, y = -row); DEAD_ENDS: open ends in the left image "
                      "(kind); REPORT: JSON with the rounds, counts, registration and times per stage; REPORT_HTML: the same for reading, with the lines drawn over the left image's frame and histograms of the lines' lengths and sigmas. Each output is written only "
                      "when asked for; at least one of OUTPUT, OUTPUT_LEFT and OUTPUT_RIGHT is needed.\n\n"
                      "POLARITY and MAPPING take their option's name (dark, bright, auto; multiquadric, projective) or its index (0, 1, 2; 0, 1)." );
}

ExtractRoadsAlgorithm *ExtractRoadsAlgorithm::createInstance() const { return new ExtractRoadsAlgorithm(); }

void ExtractRoadsAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "LEFT" ), QObject::tr( "Left image id" ) ) );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "RIGHT" ), QObject::tr( "Right image id" ) ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "DEM" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "MEAN_HEIGHT_M" ), QObject::tr( "Mean terrain height (m; empty: estimated)" ), QgsProcessingParameterNumber::Double, QVariant(), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "ROAD_WIDTH_MIN_M" ), QObject::tr( "Narrowest road (m on the ground)" ), QgsProcessingParameterNumber::Double, 3.0, false, 0.01, 1000.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "ROAD_WIDTH_MAX_M" ), QObject::tr( "Widest road (m on the ground)" ), QgsProcessingParameterNumber::Double, 30.0, false, 0.01, 1000.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "ROAD_WIDTH_MIN_PX" ), QObject::tr( "Narrowest road (px; instead of metres)" ), QgsProcessingParameterNumber::Double, QVariant(), true, 1.0, 200.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "ROAD_WIDTH_MAX_PX" ), QObject::tr( "Widest road (px; instead of metres)" ), QgsProcessingParameterNumber::Double, QVariant(), true, 1.0, 200.0 ) );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "POLARITY" ), QObject::tr( "Roads are" ), kPolarities, false, QStringLiteral( "auto" ), false, true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "MIN_CONTRAST" ), QObject::tr( "Minimum contrast (grey levels; empty: from the image's texture)" ), QgsProcessingParameterNumber::Double, QVariant(), true, 1.0, 255.0 ) );
  auto spacing = std::make_unique<QgsProcessingParameterNumber>( QStringLiteral( "START_SPACING_PX" ), QObject::tr( "Starting-point sample lines every (px)" ),
                                                                  QgsProcessingParameterNumber::Integer, 48, false, 4, 1000 );
  spacing->setFlags( spacing->flags() | QgsProcessingParameterDefinition::FlagAdvanced );
  addParameter( spacing.release() );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "CONTROL" ), QObject::tr( "Control-point pairs (unoriented pair)" ), QList<int>() << QgsProcessing::TypeVector, QVariant(), true ) );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "MAPPING" ), QObject::tr( "Mapping from control points" ), kMappings, false, QStringLiteral( "multiquadric" ), false, true ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Road network (3-D)" ), QgsProcessing::TypeVectorLine, QVariant(), true ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT_LEFT" ), QObject::tr( "Roads in the left image" ), QgsProcessing::TypeVectorLine, QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT_RIGHT" ), QObject::tr( "Roads in the right image" ), QgsProcessing::TypeVectorLine, QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "DEAD_ENDS" ), QObject::tr( "Open ends (left image)" ), QgsProcessing::TypeVectorPoint, QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
  addParameter( GeoStationProcessing::htmlReportParameter() );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "LINE_COUNT" ), QObject::tr( "Lines in the left image" ) ) );
}

QVariantMap ExtractRoadsAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const geostation::BlockImage &left = GeoStationProcessing::blockImage( block, parameterAsString( parameters, QStringLiteral( "LEFT" ), context ).trimmed() );
  const geostation::BlockImage &right = GeoStationProcessing::blockImage( block, parameterAsString( parameters, QStringLiteral( "RIGHT" ), context ).trimmed() );
  if ( left.id == right.id )
    throw QgsProcessingException( QObject::tr( "LEFT and RIGHT are the same image (%1): a stereo pair needs two." ).arg( QString::fromStdString( left.id ) ) );

  geostation::RoadNetworkOptions options = geostation::defaultRoadNetworkOptions();
  options.roadWidthM.reset();
  geostation::LineObjectOptions &object = options.coincident.extraction.object;
  const QString polarity = parameterAsEnumString( parameters, QStringLiteral( "POLARITY" ), context );
  object.polarity = polarity == QLatin1String( "bright" ) ? 1 : polarity == QLatin1String( "dark" ) ? -1 : 0;
  if ( GeoStationProcessing::hasParameterValue( parameters, QStringLiteral( "MIN_CONTRAST" ) ) )
  {
    object.minContrast = parameterAsDouble( parameters, QStringLiteral( "MIN_CONTRAST" ), context );
    options.contrastPerTexture = 0.0; // the given contrast, not one from the texture
  }
  const bool minPx = GeoStationProcessing::hasParameterValue( parameters, QStringLiteral( "ROAD_WIDTH_MIN_PX" ) ), maxPx = GeoStationProcessing::hasParameterValue( parameters, QStringLiteral( "ROAD_WIDTH_MAX_PX" ) );
  if ( minPx )
    object.minWidthPx = parameterAsDouble( parameters, QStringLiteral( "ROAD_WIDTH_MIN_PX" ), context );
  if ( maxPx )
    object.maxWidthPx = parameterAsDouble( parameters, QStringLiteral( "ROAD_WIDTH_MAX_PX" ), context );
  if ( minPx && !maxPx && object.maxWidthPx < object.minWidthPx )
    object.maxWidthPx = object.minWidthPx;
  if ( maxPx && !minPx && object.minWidthPx > object.maxWidthPx )
    object.minWidthPx = object.maxWidthPx;
  const double minM = parameterAsDouble( parameters, QStringLiteral( "ROAD_WIDTH_MIN_M" ), context ), maxM = parameterAsDouble( parameters, QStringLiteral( "ROAD_WIDTH_MAX_M" ), context );
  if ( !( maxM >= minM ) )
    throw QgsProcessingException( QObject::tr( "ROAD_WIDTH_MAX_M (%1 m) is less than ROAD_WIDTH_MIN_M (%2 m)." ).arg( maxM ).arg( minM ) );
  if ( !minPx && !maxPx )
    options.roadWidthM = std::make_pair( minM, maxM ); // used for an oriented pair
  options.coincident.extraction.start.sampleSpacingPx = parameterAsInt( parameters, QStringLiteral( "START_SPACING_PX" ), context );
  if ( parameters.value( QStringLiteral( "MEAN_HEIGHT_M" ) ).isValid() && !parameters.value( QStringLiteral( "MEAN_HEIGHT_M" ) ).toString().isEmpty() )
    options.meanHeightM = parameterAsDouble( parameters, QStringLiteral( "MEAN_HEIGHT_M" ), context );
  if ( std::unique_ptr<QgsProcessingFeatureSource> control { parameterAsSource( parameters, QStringLiteral( "CONTROL" ), context ) } )
    options.control = GeoStationProcessing::readControlPairs( control.get() );
  options.controlMapping = parameterAsEnumString( parameters, QStringLiteral( "MAPPING" ), context ) == QLatin1String( "projective" ) ? geostation::ControlMapping::Projective
                           : geostation::ControlMapping::Multiquadric;
  const bool oriented = left.exterior && right.exterior && options.control.empty();
  std::optional<geostation::OrientedImage> orientedLeft, orientedRight;
  if ( oriented )
  {
    orientedLeft.emplace( GeoStationProcessing::orientedImage( block, left ) );
    orientedRight.emplace( GeoStationProcessing::orientedImage( block, right ) );
  }
  else if ( options.control.empty() )
    throw QgsProcessingException( QObject::tr( "The pair is not oriented: give CONTROL, a table of point pairs (point_id, col_left, row_left, col_right, row_right)." ) );
  const bool imageOutputs = outputRequested( parameters, QStringLiteral( "OUTPUT_LEFT" ) ) || outputRequested( parameters, QStringLiteral( "OUTPUT_RIGHT" ) );
  if ( !imageOutputs && !( oriented && outputRequested( parameters, QStringLiteral( "OUTPUT" ) ) ) )
    throw QgsProcessingException( oriented ? QObject::tr( "Nothing would be written: give OUTPUT (the 3-D network), OUTPUT_LEFT or OUTPUT_RIGHT." )
                                           : QObject::tr( "Nothing would be written: a pair registered by CONTROL has lines in image space only; give OUTPUT_LEFT or OUTPUT_RIGHT." ) );
  GeoStationProcessing::LoadedDem dem;
  if ( QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
    dem = GeoStationProcessing::loadDem( demLayer->source(), block );
  if ( dem.dem )
    options.terrain = geostation::demHeightAt( *dem.dem, *dem.blockToDem );
  geostation::RoadNetworkSummary s;
  const geostation::Progress progress = GeoStationProcessing::progressOf( feedback );
  const geostation::OrientedImage *a = orientedLeft ? &*orientedLeft : nullptr, *b = orientedRight ? &*orientedRight : nullptr;
  // read a window at a time: memory does not grow with the images (beyond a byte a pixel for the result matrices)
  const std::shared_ptr<const geostation::RasterReader> leftFile = GeoStationProcessing::openImageFile( block, left );
  s = geostation::extractRoadNetwork( leftFile, GeoStationProcessing::openImageFile( block, right ), a, b, options, progress );
  if ( s.extraction.cancelled )
    throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );
  if ( s.extraction.linesA.empty() )
    feedback->pushWarning( QObject::tr( "No road was found in the pair (the layers are empty)." ) );

  // outputs, only now
  QgsFields lineFields;
  lineFields.append( QgsField( QLatin1String( fs::kLineId ), QVariant::Int ) );
  lineFields.append( QgsField( QLatin1String( fs::kAcceptedIn ), QVariant::String ) );
  QVariantMap outputs;
  const auto imageSink = [&]( const QString &name, const std::vector<geostation::CompiledPolygon> &lines, bool inLeft )
  {
    if ( !outputRequested( parameters, name ) )
      return;
    OutputSink sink = openOutput( parameters, name, context, lineFields, QgsWkbTypes::LineString, QgsCoordinateReferenceSystem() );
    for ( size_t i = 0; i < lines.size(); ++i )
    {
      QgsFeature f( lineFields );
      f.setAttributes( QgsAttributes() << static_cast<int>( i + 1 ) << acceptedIn( lines[i].symbols, inLeft ) );
      f.setGeometry( imageSpaceLine( lines[i].pixels ) );
      sink.add( f );
    }
    sink.close();
    GeoStationProcessing::markPixelSpaceOutput( sink.destination() );
    outputs.insert( name, sink.destination() );
  };
  imageSink( QStringLiteral( "OUTPUT_LEFT" ), s.extraction.linesA, true );
  imageSink( QStringLiteral( "OUTPUT_RIGHT" ), s.extraction.linesB, false );

  if ( s.oriented )
  {
    QgsFields fields = lineFields;
    fields.append( QgsField( QLatin1String( fs::kLengthM ), QVariant::Double ) );
    fields.append( QgsField( QLatin1String( fs::kSigmaMax ), QVariant::Double ) );
    if ( outputRequested( parameters, QStringLiteral( "OUTPUT" ) ) )
    {
      OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::LineStringZ, GeoStationProcessing::blockCrs( block ) );
      for ( const geostation::NetworkLine &line : s.network.lines )
      {
        QVector<double> x, y, z;
        for ( const geostation::NetworkVertex &v : line.vertices )
        {
          x << v.point.x();
          y << v.point.y();
          z << v.point.z();
        }
        QgsFeature f( fields );
        f.setAttributes( QgsAttributes() << line.sourceLine + 1 << acceptedIn( s.extraction.linesA[line.sourceLine].symbols, true ) << line.lengthM() << line.sigmaMaxM() );
        f.setGeometry( QgsGeometry( new QgsLineString( x, y, z ) ) );
        sink.add( f );
      }
      outputs.insert( QStringLiteral( "OUTPUT" ), sink.close() );
    }
  }

  QgsFields endFields;
  endFields.append( QgsField( QStringLiteral( "kind" ), QVariant::String ) );
  if ( outputRequested( parameters, QStringLiteral( "DEAD_ENDS" ) ) )
  {
    OutputSink ends = openOutput( parameters, QStringLiteral( "DEAD_ENDS" ), context, endFields, QgsWkbTypes::Point );
    for ( const geostation::DeadEnd &d : s.extraction.deadEndsA )
    {
      QgsFeature f( endFields );
      f.setAttributes( QgsAttributes() << QString::fromStdString( geostation::deadEndKindName( d.kind ) ) );
      const Eigen::Vector2d xy = geostation::imageSpaceOfPixel( d.state.pixelInImage );
      f.setGeometry( QgsGeometry( new QgsPoint( xy.x(), xy.y() ) ) );
      ends.add( f );
    }
    GeoStationProcessing::markPixelSpaceOutput( ends.close() );
    outputs.insert( QStringLiteral( "DEAD_ENDS" ), ends.destination() );
  }

  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  const QString htmlPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT_HTML" ), context );
  const QString leftId = QString::fromStdString( left.id ), rightId = QString::fromStdString( right.id );
  GeoStationProcessing::writeReports( { { reportPath, reportPath.isEmpty() ? QByteArray() : GeoStationProcessing::jsonReport( GeoStationProcessing::extractRoadsReport( s, leftId, rightId, options.control ) ) },
                                        { htmlPath, htmlPath.isEmpty() ? QByteArray() : GeoStationProcessing::extractRoadsHtml( s, leftId, rightId, options.control, leftFile->size().width, leftFile->size().height ) } } );
  if ( !reportPath.isEmpty() )
    outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  if ( !htmlPath.isEmpty() )
    outputs.insert( QStringLiteral( "REPORT_HTML" ), htmlPath );
  outputs.insert( QStringLiteral( "LINE_COUNT" ), static_cast<int>( s.extraction.linesA.size() ) );
  feedback->pushInfo( QObject::tr( "%1 lines in the left image, %2 in the right, %3 rounds, %4 s (mapping: %5)." ).arg( s.extraction.linesA.size() )
                      .arg( s.extraction.linesB.size() ).arg( s.extraction.rounds.size() ).arg( s.seconds, 0, 'f', 2 ).arg( QString::fromStdString( s.mapping ) ) );
  return outputs;
}

} // namespace GeoStationProcessing
