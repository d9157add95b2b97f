/***************************************************************************
  traceroadlinesalgorithm.cpp - geostation:trace_road_lines
  -------------------------------------------------------------------------
  Seeds (one click per line) in, one LineStringZ per seed out: the line
  followed through the run by core/tracing (thesis ch. 6). Every seed is
  traced before any output is created; a seed that cannot be traced gets
  an empty geometry and its stop reason, and the run fails only when no
  seed at all could be traced.
 ***************************************************************************/
#include "traceroadlinesalgorithm.h"

#include <optional>
#include <cmath>

#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsgeometry.h>
#include <qgslinestring.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsrasterlayer.h>

#include "dem/demintersection.h"
#include "io/featureschema.h"
#include "processingblock.h"
#include "processingtables.h"
#include "tracing/roadtracer.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

namespace
{
  const QStringList kMethods { QStringLiteral( "auto" ), QStringLiteral( "directional" ), QStringLiteral( "least_squares" ), QStringLiteral( "polynomial" ) };
}

QString TraceRoadLinesAlgorithm::name() const { return QStringLiteral( "trace_road_lines" ); }
QString TraceRoadLinesAlgorithm::displayName() const { return QObject::tr( "Trace road lines through the run" ); }
QStringList TraceRoadLinesAlgorithm::tags() const { return QObject::tr( "road,lane,marking,kerb,edge,tracing,following,mobile mapping,3d,stereo" ).split( ',' ); }
QString TraceRoadLinesAlgorithm::group() const { return QObject::tr( "Image processing" ); }
QString TraceRoadLinesAlgorithm::groupId() const { return QStringLiteral( "imageprocessing" ); }

QString TraceRoadLinesAlgorithm::helpText() const
{
  return QObject::tr( "Follows road lines (painted markings, centre lines, kerbs) from one seed each through the stations of a "
                      "mobile-mapping run and returns them as 3-D lines in the block CRS.\n\n"
                      "SEEDS: seed_id, image_id, col, row (pixels, docs/conventions.md §1) and optionally direction_deg (0 = up the "
                      "image, clockwise). At each station the line is followed in the seed's camera up to MAX_RANGE_M, found "
                      "in the station's stereo partner along the epipolar curves, and intersected with standard deviations "
                      "(pixels and the images' GNSS/INS sigmas); then it is carried to the next station. The road surface is "
                      "the plane CAMERA_HEIGHT_M below the cameras, following the track, or the DEM when one is given.\n\n"
                      "METHOD: auto, directional (matrices on the thinned edge image), least_squares (row-by-row shifts) or "
                      "polynomial (second-order strips). MAX_STATIONS 0 traces to the end of the run.\n\n"
                      "OUTPUT: one LineStringZ per seed with seed_id, method, stations, length_m, sigma_max, stop_reason and "
                      "message; a seed that cannot be traced keeps its row with an empty geometry. VERTICES (optional): "
                      "seed_id, vertex, X, Y, Z, sx, sy, sz, station, image_ids, residuals_px." );
}

TraceRoadLinesAlgorithm *TraceRoadLinesAlgorithm::createInstance() const { return new TraceRoadLinesAlgorithm(); }

void TraceRoadLinesAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "SEEDS" ), QObject::tr( "Seeds (seed_id, image_id, col, row [, direction_deg])" ), QList<int>() << QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "DEM (instead of the road plane)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "METHOD" ), QObject::tr( "Method" ), kMethods, false, QStringLiteral( "auto" ), false, true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "MAX_STATIONS" ), QObject::tr( "Stations to trace (0 = to the end of the run)" ), QgsProcessingParameterNumber::Integer, 0, false, 0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "MAX_RANGE_M" ), QObject::tr( "Distance limit from the cameras (m)" ), QgsProcessingParameterNumber::Double, 20.0, false, 6.0, 200.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "CAMERA_HEIGHT_M" ), QObject::tr( "Camera height above the road (m)" ), QgsProcessingParameterNumber::Double, 2.6, false, 0.1, 100.0 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Traced lines" ), QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "VERTICES" ), QObject::tr( "Vertices" ), QgsProcessing::TypeVector, QVariant(), true, false ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "TRACED_COUNT" ), QObject::tr( "Seeds traced" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "FAILED_COUNT" ), QObject::tr( "Seeds not traced" ) ) );
}

QVariantMap TraceRoadLinesAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QgsCoordinateReferenceSystem crs = GeoStationProcessing::blockCrs( block );
  std::unique_ptr<QgsProcessingFeatureSource> source( parameterAsSource( parameters, QStringLiteral( "SEEDS" ), context ) );
  if ( !source )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "SEEDS" ) ) );
  const QVector<GeoStationProcessing::TraceSeedRecord> seeds = GeoStationProcessing::readTraceSeeds( source.get() );
  for ( const GeoStationProcessing::TraceSeedRecord &r : seeds )
    GeoStationProcessing::orientedImage( block, GeoStationProcessing::blockImage( block, QString::fromStdString( r.seed.imageId ) ) ); // unknown or unoriented: one sentence, before any output

  geostation::RoadTraceOptions options;
  options.method = geostation::traceMethodFromName( parameterAsEnumString( parameters, QStringLiteral( "METHOD" ), context ).toStdString() );
  options.maxStations = parameterAsInt( parameters, QStringLiteral( "MAX_STATIONS" ), context );
  options.maxRangeM = parameterAsDouble( parameters, QStringLiteral( "MAX_RANGE_M" ), context );
  options.cameraHeightM = parameterAsDouble( parameters, QStringLiteral( "CAMERA_HEIGHT_M" ), context );
  std::unique_ptr<geostation::Dem> dem;
  std::unique_ptr<geostation::CrsTransform> blockToDem;
  if ( QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
  {
    GeoStationProcessing::LoadedDem loaded = GeoStationProcessing::loadDem( demLayer->source(), block );
    dem = std::move( loaded.dem );
    blockToDem = std::move( loaded.blockToDem );
    options.groundOfPixel = [&]( const geostation::OrientedImage &image, const Eigen::Vector2d &pixel ) -> std::optional<Eigen::Vector3d>
    {
      const std::optional<geostation::Ray> ray = image.worldRayFromPixel( pixel );
      if ( !ray )
        return std::nullopt;
      const geostation::DemIntersection hit = geostation::intersectRayWithDem( *ray, *dem, *blockToDem );
      return hit.hit() ? std::optional<Eigen::Vector3d>( hit.point ) : std::nullopt;
    };
  }
  options.check();

  // trace every seed first: no output file exists until there is something to write
  std::vector<geostation::RoadTraceSummary> results;
  const geostation::GreyImageSource images = geostation::fileGreyImageSource( block );
  int traced = 0;
  for ( int i = 0; i < seeds.size(); ++i )
  {
    if ( feedback->isCanceled() )
      break;
    options.progress = GeoStationProcessing::progressOf( feedback ).part( static_cast<double>( i ) / seeds.size(), static_cast<double>( i + 1 ) / seeds.size() );
    results.push_back( geostation::traceRoadLine( block, seeds[i].seed, options, images ) );
    const geostation::RoadTraceSummary &s = results.back();
    if ( s.ok() )
    {
      ++traced;
      feedback->pushInfo( QObject::tr( "Seed %1: %2 m over %3 stations (%4); stopped: %5." )
                          .arg( QString::fromStdString( seeds[i].seed.id ) ).arg( s.lengthM, 0, 'f', 1 ).arg( s.stations.size() )
                          .arg( QString::fromStdString( s.methods() ), QString::fromStdString( s.message ) ) );
      if ( s.multiStation.redundancy > 0 )
        feedback->pushInfo( QObject::tr( "Seed %1: sigma0 a posteriori %2 (redundancy %3)%4." )
                            .arg( QString::fromStdString( seeds[i].seed.id ) ).arg( s.sigma0, 0, 'f', 2 ).arg( s.multiStation.redundancy )
                            .arg( s.sigmaScaled ? QObject::tr( ", the vertices' sigmas scaled by it" ) : QString() ) );
    }
    else
      feedback->pushWarning( QObject::tr( "Seed %1 was not traced: %2." ).arg( QString::fromStdString( seeds[i].seed.id ), QString::fromStdString( s.message ) ) );
  }
  if ( traced == 0 )
  {
    QString why = results.empty() ? QObject::tr( "cancelled" ) : QString::fromStdString( results.front().message );
    throw QgsProcessingException( QObject::tr( "No seed could be traced (first: %1)." ).arg( why ) );
  }

  QgsFields fields = source->fields();
  const auto addField = [&]( const QString &name, QVariant::Type type )
  {
    if ( fields.lookupField( name ) < 0 )
      fields.append( QgsField( name, type ) );
  };
  addField( QLatin1String( fs::kSeedId ), QVariant::String );
  addField( QLatin1String( fs::kMethod ), QVariant::String );
  addField( QStringLiteral( "stations" ), QVariant::Int );
  addField( QLatin1String( fs::kLengthM ), QVariant::Double );
  addField( QLatin1String( fs::kSigmaMax ), QVariant::Double );
  addField( QLatin1String( fs::kStopReason ), QVariant::String );
  addField( QLatin1String( fs::kMessage ), QVariant::String );
  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::LineStringZ, crs );
  QgsFields vertexFields;
  for ( const auto &[name, type] : std::vector<std::pair<const char *, QVariant::Type>> { { "seed_id", QVariant::String }, { fs::kVertex, QVariant::Int }, { fs::kX, QVariant::Double },
        { fs::kY, QVariant::Double }, { fs::kZ, QVariant::Double }, { fs::kSx, QVariant::Double }, { fs::kSy, QVariant::Double }, { fs::kSz, QVariant::Double },
        { fs::kStation, QVariant::String }, { fs::kImageIds, QVariant::String }, { fs::kResidualsPx, QVariant::String } } )
    vertexFields.append( QgsField( QString::fromLatin1( name ), type ) );
  std::optional<OutputSink> vertexSink;
  if ( outputRequested( parameters, QStringLiteral( "VERTICES" ) ) )
    vertexSink.emplace( openOutput( parameters, QStringLiteral( "VERTICES" ), context, vertexFields, QgsWkbTypes::NoGeometry ) );

  for ( size_t i = 0; i < results.size(); ++i )
  {
    const geostation::RoadTraceSummary &s = results[i];
    QgsFeature f( fields );
    QgsAttributes attributes = seeds[i].attributes;
    attributes.resize( fields.size() );
    const auto set = [&]( const QString &name, const QVariant &value ) { attributes[fields.lookupField( name )] = value; };
    set( QLatin1String( fs::kSeedId ), QString::fromStdString( seeds[i].seed.id ) );
    set( QLatin1String( fs::kMethod ), QString::fromStdString( s.methods() ) );
    set( QStringLiteral( "stations" ), static_cast<int>( s.stations.size() ) );
    set( QLatin1String( fs::kLengthM ), s.lengthM );
    set( QLatin1String( fs::kSigmaMax ), s.sigmaMaxM );
    set( QLatin1String( fs::kStopReason ), QString::fromStdString( geostation::traceStopName( s.stop ) ) );
    set( QLatin1String( fs::kMessage ), QString::fromStdString( s.message ) );
    f.setAttributes( attributes );
    if ( s.ok() )
    {
      QVector<double> x, y, z;
      for ( const geostation::TracedVertex &v : s.vertices )
      {
        x << v.point.x();
        y << v.point.y();
        z << v.point.z();
      }
      f.setGeometry( QgsGeometry( new QgsLineString( x, y, z ) ) );
    }
    sink.add( f );
    if ( !vertexSink )
      continue;
    for ( size_t k = 0; k < s.vertices.size(); ++k )
    {
      const geostation::TracedVertex &v = s.vertices[k];
      QStringList ids, residuals;
      for ( size_t j = 0; j < v.imageIds.size(); ++j )
      {
        ids << QString::fromStdString( v.imageIds[j] );
        residuals << QStringLiteral( "%1 %2" ).arg( v.residualsPx[j].x(), 0, 'f', 3 ).arg( v.residualsPx[j].y(), 0, 'f', 3 );
      }
      QgsFeature vf( vertexFields );
      vf.setAttributes( QgsAttributes() << QString::fromStdString( seeds[i].seed.id ) << static_cast<int>( k ) << v.point.x() << v.point.y() << v.point.z() << v.sigmaM.x()
                        << v.sigmaM.y() << v.sigmaM.z() << QString::fromStdString( v.stationId ) << ids.join( ';' ) << residuals.join( ';' ) );
      vertexSink->add( vf );
    }
  }
  sink.close( true ); // a seed not traced: its row and reason, no geometry
  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), sink.destination() );
  if ( vertexSink )
    outputs.insert( QStringLiteral( "VERTICES" ), vertexSink->close() );
  outputs.insert( QStringLiteral( "TRACED_COUNT" ), traced );
  outputs.insert( QStringLiteral( "FAILED_COUNT" ), static_cast<int>( results.size() ) - traced );
  return outputs;
}

} // namespace GeoStationProcessing
