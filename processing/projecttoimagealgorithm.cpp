/***************************************************************************
  projecttoimagealgorithm.cpp - geostation:project_to_image
 ***************************************************************************/
#include "projecttoimagealgorithm.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsfeature.h>
#include <qgsfeaturesink.h>
#include <qgsgeometry.h>
#include <qgslinestring.h>
#include <qgspoint.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsprocessingutils.h>
#include <qgsrasterlayer.h>

#include "dem/monoplotter.h"
#include "geometryprojector.h"
#include "processingblock.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

namespace
{
  //! One input feature, projected, waiting to be written.
  struct ProjectedFeature
  {
    QgsFeature feature;
    QgsGeometry geometryInImage; //!< null when any part is behind the camera
    bool projected = false;
    bool inFrame = false;
    bool visible = false;
    QVariant col, row, depthM;
    QString status = QStringLiteral( "ok" ); //!< or why not: behind_camera, outside_field, no_height, outside_dem, transform_failed
    QString message;
  };
} // namespace

QString ProjectToImageAlgorithm::name() const { return QStringLiteral( "project_to_image" ); }
QString ProjectToImageAlgorithm::displayName() const { return QObject::tr( "Project map features to image" ); }
QStringList ProjectToImageAlgorithm::tags() const { return QObject::tr( "photogrammetry,collinearity,image,pixel,back-projection,monoplotting" ).split( ',' ); }
QString ProjectToImageAlgorithm::group() const { return QObject::tr( "Monoplotting" ); }
QString ProjectToImageAlgorithm::groupId() const { return QStringLiteral( "monoplotting" ); }

QString ProjectToImageAlgorithm::helpText() const
{
  return QObject::tr( "Projects map features with heights (or draped on a DEM) into one oriented image of a GeoStation "
                      "block, using the collinearity equations with the camera's lens distortion. Lines and polygon "
                      "rings are densified until no projected segment exceeds DENSIFY_PX pixels, so a straight map "
                      "segment follows its curve in the photo.\n\n"
                      "The output is an image-space layer without CRS: x = col, y = -row in pixels (origin at the "
                      "top-left corner of the image), so it overlays the raw image in QGIS. Input attributes are kept; "
                      "the fields col, row (pixels, for single points), depth_m (smallest distance in front of the camera "
                      "along its axis), in_frame and visible (for every vertex) are added.\n\n"
                      "A point behind the camera, or far outside its field of view (more than twice the frame-corner angle, "
                      "where the lens distortion model is extrapolated), is never projected: its feature has no geometry and "
                      "in_frame = visible = false. A line is cut where it leaves that field, and a polygon is clipped to it "
                      "in 3D (at 1 cm in front of the camera and inside the lens field) before it is projected; both are "
                      "counted in CLIPPED_COUNT. A line cut into several parts keeps its longest part, a part of a "
                      "multi-line keeps all of them.\n\n"
                      "With a DEM, points without Z take the DEM's height, and visible tells whether the terrain hides "
                      "the point from the camera. Without a DEM no occlusion test is possible, so visible = in_frame.\n\n"
                      "Every feature gets a status - ok, behind_camera, outside_field, or, for a feature that cannot be "
                      "placed at all, no_height, outside_dem or transform_failed with the sentence in message - and the "
                      "others go on. The run fails only when no feature is projected because of such problems." );
}

ProjectToImageAlgorithm *ProjectToImageAlgorithm::createInstance() const { return new ProjectToImageAlgorithm(); }

void ProjectToImageAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "IMAGE" ), QObject::tr( "Image id" ) ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "INPUT" ), QObject::tr( "Map features (with Z, or draped on the DEM)" ),
                QList<int>() << QgsProcessing::TypeVectorAnyGeometry ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "DEM (heights for 2D points, occlusion test)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "DENSIFY_PX" ), QObject::tr( "Densify lines to (pixels)" ), QgsProcessingParameterNumber::Double, 5.0, false, 0.1 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Features in image space" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "PROJECTED_COUNT" ), QObject::tr( "Features projected" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "IN_FRAME_COUNT" ), QObject::tr( "Features in the frame" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "BEHIND_CAMERA_COUNT" ), QObject::tr( "Features behind the camera" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "CLIPPED_COUNT" ), QObject::tr( "Lines and polygons cut at the camera plane" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "UNRESOLVED_COUNT" ), QObject::tr( "Features without a height, outside the DEM or not transformable" ) ) );
}

QVariantMap ProjectToImageAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  // everything that can fail is checked before the output exists: bad input leaves no partial file
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QString imageId = parameterAsString( parameters, QStringLiteral( "IMAGE" ), context ).trimmed();
  const geostation::BlockImage &image = GeoStationProcessing::blockImage( block, imageId );
  const geostation::OrientedImage orientedImage = GeoStationProcessing::orientedImage( block, image );
  GeoStationProcessing::requireImageFile( block, image );
  const QgsCoordinateReferenceSystem blockCrs = GeoStationProcessing::blockCrs( block );

  GeoStationProcessing::LoadedDem dem;
  std::unique_ptr<geostation::Monoplotter> monoplotter; // with a DEM: heights for 2-D features, occlusion
  if ( QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
  {
    dem = GeoStationProcessing::loadDem( demLayer->source(), block );
    monoplotter = std::make_unique<geostation::Monoplotter>( orientedImage, *dem.dem, *dem.blockToDem );
  }

  std::unique_ptr<QgsProcessingFeatureSource> source( parameterAsSource( parameters, QStringLiteral( "INPUT" ), context ) );
  if ( !source )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "INPUT" ) ) );
  if ( !QgsWkbTypes::hasZ( source->wkbType() ) && !monoplotter )
    throw QgsProcessingException( QObject::tr( "The input layer has no Z values; without a DEM, points need heights (PointZ) to be projected into the image." ) );

  const QgsCoordinateReferenceSystem sourceCrs = source->sourceCrs().isValid() ? source->sourceCrs() : blockCrs;
  if ( !source->sourceCrs().isValid() )
    feedback->pushWarning( QObject::tr( "The input layer has no CRS; its coordinates are taken to be in the block CRS %1." ).arg( blockCrs.userFriendlyIdentifier() ) );
  const QgsCoordinateTransform toBlock( sourceCrs, blockCrs, context.transformContext() );

  // heights of inserted line points come from the DEM when the layer's came from it
  const GeoStationProcessing::GeometryProjector projector( orientedImage, monoplotter.get(), toBlock, parameterAsDouble( parameters, QStringLiteral( "DENSIFY_PX" ), context ) );

  std::vector<ProjectedFeature> results;
  results.reserve( static_cast<size_t>( std::max<long long>( 0, source->featureCount() ) ) );
  const double step = source->featureCount() > 0 ? 90.0 / source->featureCount() : 0;
  QgsFeatureIterator it = source->getFeatures( QgsFeatureRequest(), QgsProcessingFeatureSource::FlagSkipGeometryValidityChecks );
  QgsFeature feature;
  long long behindCount = 0, outsideFieldCount = 0, clippedCount = 0, unresolvedCount = 0;
  QString firstProblem;
  while ( it.nextFeature( feature ) )
  {
    if ( feedback->isCanceled() )
      return QVariantMap();
    ProjectedFeature out;
    out.feature = feature;
    if ( feature.hasGeometry() )
    {
      geostation::FeatureProjectionTally c;
      std::unique_ptr<QgsAbstractGeometry> inImage;
      try
      {
        inImage = projector.project( feature.geometry().constGet(), feature.id(), c );
        out.depthM = std::isfinite( c.minDepthM ) ? QVariant( c.minDepthM ) : QVariant();
        if ( !inImage )
        {
          behindCount += c.behind ? 1 : 0;
          outsideFieldCount += !c.behind ? 1 : 0;
          out.status = c.behind ? QStringLiteral( "behind_camera" ) : QStringLiteral( "outside_field" );
        }
      }
      catch ( const GeoStationProcessing::FeatureProblem &problem )
      {
        out.status = problem.status;
        out.message = problem.message;
        if ( ++unresolvedCount <= 20 )
          feedback->pushWarning( problem.message );
        firstProblem = firstProblem.isEmpty() ? problem.message : firstProblem;
      }
      if ( inImage )
      {
        clippedCount += c.clipped ? 1 : 0;
        out.projected = true;
        out.inFrame = c.allInFrame;
        // Without a DEM nothing can hide a point: visible = in frame.
        out.visible = c.allInFrame && ( !monoplotter || c.allVisible );
        if ( const QgsPoint *single = qgsgeometry_cast<const QgsPoint *>( inImage.get() ) )
        {
          out.col = single->x();
          out.row = -single->y();
        }
        out.geometryInImage = QgsGeometry( std::move( inImage ) );
      }
    }
    results.push_back( std::move( out ) );
    feedback->setProgress( step * static_cast<double>( results.size() ) );
  }

  // a feature that cannot be projected is kept with its status; with no feature projected because of such
  // problems (no height, outside the DEM, a failed transform), the input is wrong: one sentence, no file
  if ( unresolvedCount > 0 && std::none_of( results.begin(), results.end(), []( const ProjectedFeature & r ) { return r.projected; } ) )
    throw QgsProcessingException( unresolvedCount == 1 ? firstProblem : QObject::tr( "None of the %1 features can be projected; the first: %2" ).arg( unresolvedCount ).arg( firstProblem ) );
  if ( unresolvedCount > 20 )
    feedback->pushWarning( QObject::tr( "… and %1 more features that cannot be projected (see their status and message)." ).arg( unresolvedCount - 20 ) );

  QgsFields newFields;
  newFields.append( QgsField( QLatin1String( fs::kCol ), QVariant::Double ) );
  newFields.append( QgsField( QLatin1String( fs::kRow ), QVariant::Double ) );
  newFields.append( QgsField( QStringLiteral( "depth_m" ), QVariant::Double ) );
  newFields.append( QgsField( QStringLiteral( "in_frame" ), QVariant::Bool ) );
  newFields.append( QgsField( QStringLiteral( "visible" ), QVariant::Bool ) );
  newFields.append( QgsField( QLatin1String( fs::kStatus ), QVariant::String ) );
  newFields.append( QgsField( QLatin1String( fs::kMessage ), QVariant::String ) );
  const QgsFields outFields = QgsProcessingUtils::combineFields( source->fields(), newFields );
  const QgsWkbTypes::Type outType = QgsWkbTypes::flatType( source->wkbType() );

  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, outFields, outType, QgsCoordinateReferenceSystem() );

  long long projectedCount = 0, inFrameCount = 0;
  for ( ProjectedFeature &r : results )
  {
    QgsAttributes attributes = r.feature.attributes();
    attributes << r.col << r.row << r.depthM << QVariant( r.inFrame ) << QVariant( r.visible ) << r.status << ( r.message.isEmpty() ? QVariant() : QVariant( r.message ) );
    QgsFeature outFeature( outFields );
    outFeature.setAttributes( attributes );
    if ( r.projected )
      outFeature.setGeometry( r.geometryInImage );
    sink.add( outFeature );
    projectedCount += r.projected ? 1 : 0;
    inFrameCount += r.inFrame ? 1 : 0;
  }
  GeoStationProcessing::markPixelSpaceOutput( sink.close( true ) ); // behind the camera: its row, no NaN
  feedback->setProgress( 100 );

  feedback->pushInfo( QObject::tr( "%1 of %2 features projected into image %3 (%4 in the frame)." )
                      .arg( projectedCount ).arg( results.size() ).arg( imageId ).arg( inFrameCount ) );
  if ( clippedCount > 0 )
    feedback->pushWarning( QObject::tr( "%1 lines or polygons were cut where they pass behind the camera (or out of the lens field); a line cut into several parts keeps its longest part (a multi-line all of them)." ).arg( clippedCount ) );
  if ( behindCount > 0 )
    feedback->pushWarning( QObject::tr( "%1 features lie behind the camera and were not projected." ).arg( behindCount ) );
  if ( outsideFieldCount > 0 )
    feedback->pushWarning( QObject::tr( "%1 features lie far outside the camera's field of view, where its lens model is not valid, and were not projected." ).arg( outsideFieldCount ) );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), sink.destination() );
  outputs.insert( QStringLiteral( "PROJECTED_COUNT" ), projectedCount );
  outputs.insert( QStringLiteral( "IN_FRAME_COUNT" ), inFrameCount );
  outputs.insert( QStringLiteral( "BEHIND_CAMERA_COUNT" ), behindCount );
  outputs.insert( QStringLiteral( "CLIPPED_COUNT" ), clippedCount );
  outputs.insert( QStringLiteral( "UNRESOLVED_COUNT" ), unresolvedCount );
  return outputs;
}

} // namespace GeoStationProcessing
