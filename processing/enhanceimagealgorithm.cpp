/***************************************************************************
  enhanceimagealgorithm.cpp - geostation:enhance_image
  -------------------------------------------------------------------------
  The enhancements of core/imageproc/enhancement.h on a raster file, written
  as a GeoTIFF with the input's georeferencing.
 ***************************************************************************/
#include "enhanceimagealgorithm.h"

#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsrasterlayer.h>

#include "imageproc/enhancement.h"
#include "io/rasterfile.h"

namespace GeoStationProcessing
{

namespace
{
  const QStringList kMethods { QStringLiteral( "equalise" ), QStringLiteral( "linear" ), QStringLiteral( "two_segment" ), QStringLiteral( "three_segment" ),
                               QStringLiteral( "sobel_addback" ), QStringLiteral( "difference_addback" ), QStringLiteral( "box_filter" ) };
}

QString EnhanceImageAlgorithm::name() const
{
  return QStringLiteral( "enhance_image" );
}

QString EnhanceImageAlgorithm::displayName() const
{
  return QObject::tr( "Enhance image" );
}

QStringList EnhanceImageAlgorithm::tags() const
{
  return QObject::tr( "enhancement,stretch,contrast,equalisation,sharpen,addback,sobel,bit error,noise,filter" ).split( ',' );
}

QString EnhanceImageAlgorithm::group() const
{
  return QObject::tr( "Image processing" );
}

QString EnhanceImageAlgorithm::groupId() const
{
  return QStringLiteral( "imageprocessing" );
}

QString EnhanceImageAlgorithm::helpText() const
{
  return QObject::tr( "Enhances an 8- or 16-bit grey or RGB image for viewing and measuring, as the Geostation thesis does "
                      "(chapter 4), and writes a GeoTIFF that keeps the input's georeferencing (pixel-space images stay in "
                      "pixel space).\n\n"
                      "METHOD: equalise (histogram equalisation); linear (stretch of min..max, after CLIP_PERCENT at each "
                      "end, to OUT_LOW..OUT_HIGH); two_segment (the mean moved to PREFERRED_MEAN); three_segment (the adaptive "
                      "stretch: a = mean, b = mean + SEGMENT_WIDTH, a' = SEGMENT_TARGET; defaults 30 and 150); sobel_addback "
                      "and difference_addback (edges sharpened by adding SCALE times the strongest gradient or grey-level "
                      "difference where it exceeds THRESHOLD); box_filter (the adaptive box filter that replaces bit errors: "
                      "pixels further than BOX_C sigma and BOX_T from the mean of their BOX_WIDTH x BOX_HEIGHT box).\n\n"
                      "Levels are given on the 8-bit scale and scaled for 16-bit images. Colour images are stretched with one "
                      "mapping for all bands, so colours keep their hue. WINDOW limits the work (statistics and changes) to an "
                      "extent of the image." );
}

EnhanceImageAlgorithm *EnhanceImageAlgorithm::createInstance() const
{
  return new EnhanceImageAlgorithm();
}

void EnhanceImageAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "INPUT" ), QObject::tr( "Image" ) ) );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "METHOD" ), QObject::tr( "Method" ), kMethods, false, QStringLiteral( "three_segment" ), false, true ) );
  const auto number = [this]( const char *name, const QString &description, double value, double min, double max, bool advanced = true )
  {
    auto *p = new QgsProcessingParameterNumber( QString::fromLatin1( name ), description, QgsProcessingParameterNumber::Double, value, true, min, max );
    if ( advanced )
      p->setFlags( p->flags() | QgsProcessingParameterDefinition::FlagAdvanced );
    addParameter( p );
  };
  number( "OUT_LOW", QObject::tr( "linear: output low (0-255)" ), 0, 0, 255 );
  number( "OUT_HIGH", QObject::tr( "linear: output high (0-255)" ), 255, 0, 255 );
  number( "CLIP_PERCENT", QObject::tr( "linear: clip this % at each end" ), 0, 0, 49 );
  number( "PREFERRED_MEAN", QObject::tr( "two_segment: preferred mean (0-255)" ), 128, 1, 254 );
  number( "SEGMENT_WIDTH", QObject::tr( "three_segment: b - a (grey levels)" ), 30, 1, 254 );
  number( "SEGMENT_TARGET", QObject::tr( "three_segment: a' (grey level)" ), 150, 1, 254 );
  number( "SCALE", QObject::tr( "add-back: scale (0-1)" ), 0.5, 0.01, 0.99 );
  number( "THRESHOLD", QObject::tr( "add-back: threshold (grey levels)" ), 20, 0, 1000 );
  number( "BOX_WIDTH", QObject::tr( "box filter: width (odd, pixels)" ), 5, 3, 101 );
  number( "BOX_HEIGHT", QObject::tr( "box filter: height (odd, pixels)" ), 5, 3, 101 );
  number( "BOX_C", QObject::tr( "box filter: C (1-2)" ), 1.5, 0.5, 5 );
  number( "BOX_T", QObject::tr( "box filter: T (grey levels)" ), 10, 0, 255 );
  addParameter( new QgsProcessingParameterExtent( QStringLiteral( "WINDOW" ), QObject::tr( "Window (default: the whole image)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterRasterDestination( QStringLiteral( "OUTPUT" ), QObject::tr( "Enhanced image" ) ) );
}

QVariantMap EnhanceImageAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  QgsRasterLayer *layer = parameterAsRasterLayer( parameters, QStringLiteral( "INPUT" ), context );
  if ( !layer )
    throw QgsProcessingException( QObject::tr( "The input image cannot be read." ) );
  geostation::EnhancementOptions options;
  options.method = *geostation::enhancementMethodFromName( parameterAsEnumString( parameters, QStringLiteral( "METHOD" ), context ).toStdString() );
  const auto number = [&]( const char *name, double fallback )
  {
    const QVariant v = parameters.value( QString::fromLatin1( name ) );
    return v.isValid() && !v.isNull() && !v.toString().isEmpty() ? parameterAsDouble( parameters, QString::fromLatin1( name ), context ) : fallback;
  };
  options.outLow = number( "OUT_LOW", 0 );
  options.outHigh = number( "OUT_HIGH", 255 );
  options.clipPercent = number( "CLIP_PERCENT", 0 );
  options.preferredMean = number( "PREFERRED_MEAN", 128 );
  options.threeSegmentWidth = number( "SEGMENT_WIDTH", 30 );
  options.threeSegmentTarget = number( "SEGMENT_TARGET", 150 );
  options.scale = number( "SCALE", 0.5 );
  options.threshold = number( "THRESHOLD", 20 );
  const int boxWidth = static_cast<int>( number( "BOX_WIDTH", 5 ) ), boxHeight = static_cast<int>( number( "BOX_HEIGHT", 5 ) );
  if ( boxWidth % 2 == 0 || boxHeight % 2 == 0 )
    throw QgsProcessingException( QObject::tr( "The box filter's width and height must be odd." ) );
  options.boxHalfWidth = boxWidth / 2;
  options.boxHalfHeight = boxHeight / 2;
  options.boxC = number( "BOX_C", 1.5 );
  options.boxT = number( "BOX_T", 10 );

  geostation::RasterImage image = geostation::readRaster( layer->source().toStdString() );
  if ( parameters.value( QStringLiteral( "WINDOW" ) ).isValid() && !parameters.value( QStringLiteral( "WINDOW" ) ).toString().isEmpty() )
  {
    // the window in the layer's own coordinates (x = col, y = -row for a pixel-space image)
    const QgsRectangle extent = parameterAsExtent( parameters, QStringLiteral( "WINDOW" ), context, layer->crs() );
    const double xSize = layer->rasterUnitsPerPixelX(), ySize = layer->rasterUnitsPerPixelY();
    const QgsRectangle full = layer->extent();
    const int c0 = static_cast<int>( std::floor( ( extent.xMinimum() - full.xMinimum() ) / xSize ) );
    const int r0 = static_cast<int>( std::floor( ( full.yMaximum() - extent.yMaximum() ) / ySize ) );
    const int c1 = static_cast<int>( std::ceil( ( extent.xMaximum() - full.xMinimum() ) / xSize ) );
    const int r1 = static_cast<int>( std::ceil( ( full.yMaximum() - extent.yMinimum() ) / ySize ) );
    options.window = cv::Rect( c0, r0, c1 - c0, r1 - r0 );
  }
  feedback->setProgress( 20 );
  geostation::EnhancementSummary summary;
  const cv::Mat enhanced = geostation::enhanceImage( image.pixels, options, &summary );
  if ( feedback->isCanceled() )
    return QVariantMap();
  feedback->setProgress( 80 );
  const QString output = parameterAsOutputLayer( parameters, QStringLiteral( "OUTPUT" ), context );
  geostation::writeGeoTiffLike( output.toStdString(), enhanced, image );
  feedback->pushInfo( QObject::tr( "%1: grey levels %2..%3, mean %4%5." ).arg( QString::fromStdString( geostation::enhancementMethodName( options.method ) ) )
                      .arg( summary.min ).arg( summary.max ).arg( summary.mean, 0, 'f', 1 )
                      .arg( summary.changedPixels ? QObject::tr( "; %1 pixels changed" ).arg( summary.changedPixels ) : QString() ) );
  feedback->setProgress( 100 );
  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), output );
  return outputs;
}

} // namespace GeoStationProcessing
