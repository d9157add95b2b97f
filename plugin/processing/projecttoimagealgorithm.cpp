/***************************************************************************
  projecttoimagealgorithm.cpp - geostation:project_to_image
 ***************************************************************************/
#include "projecttoimagealgorithm.h"

#include <cmath>
#include <vector>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsfeature.h>
#include <qgsfeaturesink.h>
#include <qgsgeometry.h>
#include <qgsmultipoint.h>
#include <qgspoint.h>
#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsprocessingutils.h>
#include <qgsrasterlayer.h>

#include "dem/monoplotter.h"
#include "geometry/projection.h"
#include "processingblock.h"

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
  };
} // namespace

QString ProjectToImageAlgorithm::name() const
{
  return QStringLiteral( "project_to_image" );
}

QString ProjectToImageAlgorithm::displayName() const
{
  return QObject::tr( "Project map points to image" );
}

QStringList ProjectToImageAlgorithm::tags() const
{
  return QObject::tr( "photogrammetry,collinearity,image,pixel,back-projection,monoplotting" ).split( ',' );
}

QString ProjectToImageAlgorithm::group() const
{
  return QObject::tr( "Monoplotting" );
}

QString ProjectToImageAlgorithm::groupId() const
{
  return QStringLiteral( "monoplotting" );
}

QString ProjectToImageAlgorithm::shortHelpString() const
{
  return QObject::tr( "Projects map points with heights (PointZ) into one oriented image of a GeoStation block, "
                      "using the collinearity equations with the camera's lens distortion.\n\n"
                      "The output is an image-space layer without CRS: x = col, y = -row in pixels (origin at the "
                      "top-left corner of the image), so it overlays the raw image in QGIS. Input attributes are kept; "
                      "the fields col, row (pixels), depth_m (distance in front of the camera along its axis), "
                      "in_frame and visible are added.\n\n"
                      "A point behind the camera, or far outside its field of view (more than twice the frame-corner "
                      "angle, where the lens distortion model is extrapolated), is never projected: its feature has "
                      "no geometry and in_frame = visible = false.\n\n"
                      "With a DEM, points without Z take the DEM's height, and visible tells whether the terrain hides "
                      "the point from the camera. Without a DEM no occlusion test is possible, so visible = in_frame." );
}

ProjectToImageAlgorithm *ProjectToImageAlgorithm::createInstance() const
{
  return new ProjectToImageAlgorithm();
}

void ProjectToImageAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "IMAGE" ), QObject::tr( "Image id" ) ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "INPUT" ), QObject::tr( "Map points (with Z, or draped on the DEM)" ),
                QList<int>() << QgsProcessing::TypeVectorPoint ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "DEM (heights for 2D points, occlusion test)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Points in image space" ), QgsProcessing::TypeVectorPoint ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "PROJECTED_COUNT" ), QObject::tr( "Features projected" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "IN_FRAME_COUNT" ), QObject::tr( "Features in the frame" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "BEHIND_CAMERA_COUNT" ), QObject::tr( "Features behind the camera" ) ) );
}

QVariantMap ProjectToImageAlgorithm::processAlgorithm( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  // Everything that can fail is checked before the output is created, so bad
  // input never leaves a partial output file behind.
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QString imageId = parameterAsString( parameters, QStringLiteral( "IMAGE" ), context ).trimmed();
  const geostation::BlockImage &image = GeoStationProcessing::blockImage( block, imageId );
  const geostation::ExteriorOrientation &exterior = GeoStationProcessing::requireOriented( block, image );
  GeoStationProcessing::requireImageFile( block, image );
  const geostation::OrientedImage orientedImage( block.cameraOf( image ), exterior );
  const QgsCoordinateReferenceSystem blockCrs = GeoStationProcessing::blockCrs( block );

  std::unique_ptr<geostation::Dem> dem;
  std::unique_ptr<geostation::CrsTransform> blockToDem;
  std::unique_ptr<geostation::Monoplotter> monoplotter;
  if ( QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
  {
    try
    {
      dem = std::make_unique<geostation::Dem>( demLayer->source().toStdString() );
      blockToDem = std::make_unique<geostation::CrsTransform>( block.crs, dem->crsWkt() );
    }
    catch ( const std::exception &e )
    {
      throw QgsProcessingException( QString::fromStdString( e.what() ) );
    }
    monoplotter = std::make_unique<geostation::Monoplotter>( orientedImage, *dem, *blockToDem );
  }

  std::unique_ptr<QgsProcessingFeatureSource> source( parameterAsSource( parameters, QStringLiteral( "INPUT" ), context ) );
  if ( !source )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "INPUT" ) ) );
  if ( !QgsWkbTypes::hasZ( source->wkbType() ) && !dem )
    throw QgsProcessingException( QObject::tr( "The input layer has no Z values; without a DEM, points need heights (PointZ) to be projected into the image." ) );

  const QgsCoordinateReferenceSystem sourceCrs = source->sourceCrs().isValid() ? source->sourceCrs() : blockCrs;
  if ( !source->sourceCrs().isValid() )
    feedback->pushWarning( QObject::tr( "The input layer has no CRS; its coordinates are taken to be in the block CRS %1." ).arg( blockCrs.userFriendlyIdentifier() ) );
  const QgsCoordinateTransform toBlock( sourceCrs, blockCrs, context.transformContext() );

  std::vector<ProjectedFeature> results;
  results.reserve( static_cast<size_t>( std::max<long long>( 0, source->featureCount() ) ) );
  const double step = source->featureCount() > 0 ? 90.0 / source->featureCount() : 0;
  QgsFeatureIterator it = source->getFeatures( QgsFeatureRequest(), QgsProcessingFeatureSource::FlagSkipGeometryValidityChecks );
  QgsFeature feature;
  long long behindCount = 0, outsideFieldCount = 0;
  while ( it.nextFeature( feature ) )
  {
    if ( feedback->isCanceled() )
      return QVariantMap();
    ProjectedFeature out;
    out.feature = feature;
    if ( feature.hasGeometry() )
    {
      QgsMultiPoint partsInImage;
      bool behind = false, diverged = false, allInFrame = true, allVisible = true;
      double minDepth = std::numeric_limits<double>::infinity();
      const QgsGeometry geometry = feature.geometry();
      for ( auto vertex = geometry.vertices_begin(); vertex != geometry.vertices_end(); ++vertex )
      {
        double x = ( *vertex ).x(), y = ( *vertex ).y(), z = ( *vertex ).z();
        const bool drape = std::isnan( z );
        if ( drape && !dem )
          throw QgsProcessingException( QObject::tr( "Feature %1 has no Z value; without a DEM every point needs a height." ).arg( feature.id() ) );
        try
        {
          if ( drape )
            z = 0.0;
          toBlock.transformInPlace( x, y, z );
        }
        catch ( const QgsCsException & )
        {
          throw QgsProcessingException( QObject::tr( "Feature %1 cannot be transformed from %2 to the block CRS %3." )
                                        .arg( feature.id() ).arg( sourceCrs.userFriendlyIdentifier(), blockCrs.userFriendlyIdentifier() ) );
        }
        if ( drape )
        {
          const std::optional<double> h = monoplotter->demHeightAt( Eigen::Vector3d( x, y, 0.0 ) );
          if ( !h )
            throw QgsProcessingException( QObject::tr( "Feature %1 has no Z value and lies outside the DEM." ).arg( feature.id() ) );
          z = *h;
        }
        geostation::GroundProjection p;
        if ( monoplotter )
        {
          const geostation::MapPointInImage seen = monoplotter->groundToImage( Eigen::Vector3d( x, y, z ) );
          p = seen.projection;
          allVisible &= seen.visible;
        }
        else
          p = orientedImage.projectGroundToPixel( Eigen::Vector3d( x, y, z ) );
        minDepth = std::min( minDepth, p.depthM );
        behind |= p.status == geostation::PixelProjection::Status::BehindCamera;
        diverged |= p.status == geostation::PixelProjection::Status::DistortionDiverged || p.status == geostation::PixelProjection::Status::OutsideLensField;
        allInFrame &= p.inFrame;
        if ( p.ok() )
        {
          partsInImage.addGeometry( new QgsPoint( p.pixelInImage.x(), -p.pixelInImage.y() ) );
          out.col = p.pixelInImage.x();
          out.row = p.pixelInImage.y();
        }
      }
      out.depthM = std::isfinite( minDepth ) ? QVariant( minDepth ) : QVariant();
      if ( behind || diverged || partsInImage.numGeometries() == 0 )
      {
        behindCount += behind ? 1 : 0;
        outsideFieldCount += !behind && diverged ? 1 : 0;
        out.col = out.row = QVariant();
      }
      else
      {
        out.projected = true;
        out.inFrame = allInFrame;
        // Without a DEM nothing can hide a point: visible = in frame.
        out.visible = allInFrame && ( !monoplotter || allVisible );
        if ( partsInImage.numGeometries() == 1 && !QgsWkbTypes::isMultiType( source->wkbType() ) )
          out.geometryInImage = QgsGeometry( partsInImage.geometryN( 0 )->clone() );
        else
        {
          out.geometryInImage = QgsGeometry( partsInImage.clone() );
          out.col = out.row = QVariant(); // several parts: no single pixel
        }
      }
    }
    results.push_back( std::move( out ) );
    feedback->setProgress( step * static_cast<double>( results.size() ) );
  }

  QgsFields newFields;
  newFields.append( QgsField( QStringLiteral( "col" ), QVariant::Double ) );
  newFields.append( QgsField( QStringLiteral( "row" ), QVariant::Double ) );
  newFields.append( QgsField( QStringLiteral( "depth_m" ), QVariant::Double ) );
  newFields.append( QgsField( QStringLiteral( "in_frame" ), QVariant::Bool ) );
  newFields.append( QgsField( QStringLiteral( "visible" ), QVariant::Bool ) );
  const QgsFields outFields = QgsProcessingUtils::combineFields( source->fields(), newFields );
  const QgsWkbTypes::Type outType = QgsWkbTypes::isMultiType( source->wkbType() ) ? QgsWkbTypes::MultiPoint : QgsWkbTypes::Point;

  QString destination;
  std::unique_ptr<QgsFeatureSink> sink( parameterAsSink( parameters, QStringLiteral( "OUTPUT" ), context, destination, outFields, outType, QgsCoordinateReferenceSystem() ) );
  if ( !sink )
    throw QgsProcessingException( invalidSinkError( parameters, QStringLiteral( "OUTPUT" ) ) );

  long long projectedCount = 0, inFrameCount = 0;
  for ( ProjectedFeature &r : results )
  {
    QgsAttributes attributes = r.feature.attributes();
    attributes << r.col << r.row << r.depthM << QVariant( r.inFrame ) << QVariant( r.visible );
    QgsFeature outFeature( outFields );
    outFeature.setAttributes( attributes );
    if ( r.projected )
      outFeature.setGeometry( r.geometryInImage );
    if ( !sink->addFeature( outFeature, QgsFeatureSink::FastInsert ) )
      throw QgsProcessingException( writeFeatureError( sink.get(), parameters, QStringLiteral( "OUTPUT" ) ) );
    projectedCount += r.projected ? 1 : 0;
    inFrameCount += r.inFrame ? 1 : 0;
  }
  sink.reset(); // closes a file output
  GeoStationProcessing::markPixelSpaceOutput( destination );
  feedback->setProgress( 100 );

  feedback->pushInfo( QObject::tr( "%1 of %2 features projected into image %3 (%4 in the frame)." )
                      .arg( projectedCount ).arg( results.size() ).arg( imageId ).arg( inFrameCount ) );
  if ( behindCount > 0 )
    feedback->pushWarning( QObject::tr( "%1 features lie behind the camera and were not projected." ).arg( behindCount ) );
  if ( outsideFieldCount > 0 )
    feedback->pushWarning( QObject::tr( "%1 features lie far outside the camera's field of view, where its lens model is not valid, and were not projected." ).arg( outsideFieldCount ) );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), destination );
  outputs.insert( QStringLiteral( "PROJECTED_COUNT" ), projectedCount );
  outputs.insert( QStringLiteral( "IN_FRAME_COUNT" ), inFrameCount );
  outputs.insert( QStringLiteral( "BEHIND_CAMERA_COUNT" ), behindCount );
  return outputs;
}
