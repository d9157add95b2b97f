/***************************************************************************
  mergeroadnetworksalgorithm.cpp - geostation:merge_road_networks
  -------------------------------------------------------------------------
  Parameters -> core/extraction/networkmerge -> outputs. Each input layer
  is one pair's network, named by its `pair` field or else by the layer's
  name (a file's base name); every input is read before any output is made.
 ***************************************************************************/
#include "mergeroadnetworksalgorithm.h"

#include <cmath>
#include <memory>

#include <QJsonObject>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsfeatureiterator.h>
#include <qgsfeaturesink.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsvectorlayer.h>

#include "extraction/networkmerge.h"
#include "maproads.h"
#include "processingblock.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

namespace
{
  //! One input layer as a pair's network, in `crs` (the first layer's).
  geostation::PairNetwork readNetwork( QgsVectorLayer *layer, const QgsCoordinateReferenceSystem &crs, const QgsCoordinateTransformContext &context )
  {
    geostation::PairNetwork network;
    network.pair = layer->name().toStdString();
    const int pairField = layer->fields().lookupField( QStringLiteral( "pair" ) ), sigmaField = layer->fields().lookupField( QLatin1String( fs::kSigmaMax ) );
    const QgsCoordinateTransform transform( layer->crs(), crs, context );
    QgsFeature f;
    QgsFeatureIterator it = layer->getFeatures();
    while ( it.nextFeature( f ) )
    {
      if ( pairField >= 0 && !f.attribute( pairField ).isNull() )
        network.pair = f.attribute( pairField ).toString().toStdString();
      QgsGeometry g = f.geometry();
      if ( g.isNull() || g.isEmpty() )
        continue;
      try
      {
        g.transform( transform );
      }
      catch ( const QgsCsException & )
      {
        throw QgsProcessingException( QObject::tr( "A line of %1 cannot be carried into %2." ).arg( layer->name(), crs.userFriendlyIdentifier() ) );
      }
      const double sigma = sigmaField >= 0 ? f.attribute( sigmaField ).toDouble() : 0.0;
      for ( auto part = g.const_parts_begin(); part != g.const_parts_end(); ++part )
      {
        geostation::PairNetworkLine line;
        line.sigmaM = std::isfinite( sigma ) && sigma > 0.0 ? sigma : 0.0;
        for ( auto v = ( *part )->vertices_begin(); v != ( *part )->vertices_end(); ++v )
          line.points.emplace_back( ( *v ).x(), ( *v ).y(), std::isfinite( ( *v ).z() ) ? ( *v ).z() : 0.0 );
        network.lines.push_back( line );
      }
    }
    return network;
  }
}

QString MergeRoadNetworksAlgorithm::name() const { return QStringLiteral( "merge_road_networks" ); }
QString MergeRoadNetworksAlgorithm::displayName() const { return QObject::tr( "Merge the road networks of overlapping pairs" ); }
QStringList MergeRoadNetworksAlgorithm::tags() const { return QObject::tr( "road,network,merge,overlap,pairs,strip,block,duplicates,batch" ).split( ',' ); }
QString MergeRoadNetworksAlgorithm::group() const { return QObject::tr( "Image processing" ); }
QString MergeRoadNetworksAlgorithm::groupId() const { return QStringLiteral( "imageprocessing" ); }

QString MergeRoadNetworksAlgorithm::helpText() const
{
  return QObject::tr( "Makes one road network of the networks that Extract the road network of a stereo pair (extract_roads) "
                      "made of overlapping pairs of a block: each input layer (INPUTS) is one pair's OUTPUT, named by its pair field "
                      "or else by the layer's name.\n\n"
                      "A stretch of a line that runs along a line already merged, within the tolerance and about parallel, "
                      "is a duplicate: it is dropped and its pair is added to the line it repeats. What is left of it "
                      "continues that line where it leaves its end in its direction (a road across a pair's border, joined), "
                      "or ends on its side (a junction, whose node both lines share). Crossing roads are never duplicates, "
                      "and a pair's own lines are not compared with each other. Pairs are taken in the order of their names, "
                      "so the result does not depend on the order of the inputs.\n\n"
                      "Tolerance (m; empty: 3 times the larger sigma_max of the two lines, at least 1 m).\n\n"
                      "OUTPUT: LineStringZ in the first input's CRS with line_id, pairs (the pairs that found it, separated by ;), "
                      "length_m and sigma_max. REPORT (optional): lines and length in and out, the length dropped as duplicates, "
                      "borders joined and junctions." );
}

MergeRoadNetworksAlgorithm *MergeRoadNetworksAlgorithm::createInstance() const { return new MergeRoadNetworksAlgorithm(); }

void MergeRoadNetworksAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( new QgsProcessingParameterMultipleLayers( QStringLiteral( "INPUTS" ), QObject::tr( "Road networks of the pairs" ), QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "TOLERANCE_M" ), QObject::tr( "Tolerance (m; empty: 3 x the lines' sigma, at least 1 m)" ), QgsProcessingParameterNumber::Double, QVariant(), true, 0.001, 1000.0 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Merged road network" ), QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
}

QVariantMap MergeRoadNetworksAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const QList<QgsMapLayer *> layers = parameterAsLayerList( parameters, QStringLiteral( "INPUTS" ), context );
  if ( layers.isEmpty() )
    throw QgsProcessingException( QObject::tr( "INPUTS holds no layer: give the road networks of the pairs." ) );
  std::vector<geostation::PairNetwork> networks;
  QgsCoordinateReferenceSystem crs;
  for ( QgsMapLayer *layer : layers )
  {
    QgsVectorLayer *vector = qobject_cast<QgsVectorLayer *>( layer );
    if ( !vector || vector->geometryType() != QgsWkbTypes::LineGeometry )
      throw QgsProcessingException( QObject::tr( "%1 is not a line layer: every input is a pair's road network." ).arg( layer->name() ) );
    if ( !crs.isValid() )
      crs = vector->crs();
    networks.push_back( readNetwork( vector, crs, context.transformContext() ) );
    if ( feedback->isCanceled() )
      throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );
  }
  geostation::NetworkMergeOptions options;
  if ( GeoStationProcessing::hasParameterValue( parameters, QStringLiteral( "TOLERANCE_M" ) ) )
    options.toleranceM = parameterAsDouble( parameters, QStringLiteral( "TOLERANCE_M" ), context );
  const geostation::NetworkMergeSummary s = geostation::mergeNetworks( networks, options ); // two pairs of one name: std::invalid_argument, one sentence

  QgsFields fields;
  fields.append( QgsField( QLatin1String( fs::kLineId ), QVariant::Int ) );
  fields.append( QgsField( QLatin1String( fs::kPairs ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kLengthM ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kSigmaMax ), QVariant::Double ) );
  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::LineStringZ, crs );
  double lengthOut = 0.0;
  for ( size_t i = 0; i < s.lines.size(); ++i )
  {
    QStringList pairs;
    for ( const std::string &p : s.lines[i].pairs )
      pairs << QString::fromStdString( p );
    QgsFeature f( fields );
    f.setAttributes( QgsAttributes() << static_cast<int>( i + 1 ) << pairs.join( ';' ) << s.lines[i].lengthM() << s.lines[i].sigmaM );
    f.setGeometry( lineStringZ( s.lines[i].points ) );
    sink.add( f );
    lengthOut += s.lines[i].lengthM();
  }
  QVariantMap outputs { { QStringLiteral( "OUTPUT" ), sink.destination() } };
  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  if ( !reportPath.isEmpty() )
  {
    GeoStationProcessing::writeReport( QJsonObject { { "pairs", static_cast<int>( networks.size() ) }, { "lines_in", s.linesIn }, { "length_in_m", s.lengthInM },
                                                     { "lines_out", static_cast<int>( s.lines.size() ) }, { "length_out_m", lengthOut },
                                                     { "duplicate_length_m", s.duplicateLengthM }, { "borders_joined", s.bordersJoined }, { "junctions", s.junctions } },
                                       reportPath );
    outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  }
  feedback->pushInfo( QObject::tr( "%1 lines of %2 pairs merged into %3 (%4 m dropped as duplicates, %5 borders joined, %6 junctions)." )
                      .arg( s.linesIn ).arg( networks.size() ).arg( s.lines.size() ).arg( s.duplicateLengthM, 0, 'f', 0 ).arg( s.bordersJoined ).arg( s.junctions ) );
  return outputs;
}

} // namespace GeoStationProcessing
