// geostation:enhance_image through the processing registry: the three-segment
// stretch on a georeferenced 8-bit image (georeferencing kept), a 16-bit RGB
// window, and bad input failing with one sentence and no output.
#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <gdal.h>
#include <ogr_srs_api.h>
#include <qgsapplication.h>
#include <qgsprocessingalgorithm.h>
#include <qgsprocessingcontext.h>
#include <qgsprocessingregistry.h>
#include <qgsproject.h>

#include "geostationprovider.h"
#include "io/rasterfile.h"
#include "processingtestutils.h"

class TestEnhanceImageAlgorithm : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void threeSegmentStretchKeepsTheGeoreferencing();
    void sixteenBitRgbWindow();
    void badInputLeavesNoOutput();

  private:
    QString raster( const QString &name, int bands, GDALDataType type, bool georeferenced );
    QVariantMap run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback );
    QTemporaryDir mDir;
    QgsProcessingContext mContext;
};

void TestEnhanceImageAlgorithm::initTestCase()
{
  QVERIFY( registerGeoStationProvider() || QgsApplication::processingRegistry()->providerById( "geostation" ) );
  mContext.setProject( QgsProject::instance() );
}

QString TestEnhanceImageAlgorithm::raster( const QString &name, int bands, GDALDataType type, bool georeferenced )
{
  GDALAllRegister();
  const QString path = mDir.filePath( name );
  GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), path.toUtf8().constData(), 64, 40, bands, type, nullptr );
  if ( georeferenced )
  {
    double gt[6] = { 400000.0, 0.5, 0.0, 5000000.0, 0.0, -0.5 };
    GDALSetGeoTransform( ds, gt );
    OGRSpatialReferenceH srs = OSRNewSpatialReference( nullptr );
    OSRSetFromUserInput( srs, "EPSG:32633" );
    GDALSetSpatialRef( ds, srs );
    OSRDestroySpatialReference( srs );
  }
  const double scale = type == GDT_UInt16 ? 257.0 : 1.0;
  std::vector<double> values( 64 * 40 );
  for ( int r = 0; r < 40; ++r )
    for ( int c = 0; c < 64; ++c )
      values[r * 64 + c] = ( 40 + c + r % 4 ) * scale; // 40 .. 106
  for ( int b = 1; b <= bands; ++b )
    if ( GDALRasterIO( GDALGetRasterBand( ds, b ), GF_Write, 0, 0, 64, 40, values.data(), 64, 40, GDT_Float64, 0, 0 ) != CE_None )
      return QString();
  GDALClose( ds );
  return path;
}

QVariantMap TestEnhanceImageAlgorithm::run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback )
{
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:enhance_image" )->create() );
  return alg->run( parameters, mContext, feedback, ok );
}

void TestEnhanceImageAlgorithm::threeSegmentStretchKeepsTheGeoreferencing()
{
  const QString input = raster( "grey.tif", 1, GDT_Byte, true );
  const QString output = mDir.filePath( "grey_enhanced.tif" );
  RecordingFeedback feedback;
  bool ok = false;
  run( { { "INPUT", input }, { "METHOD", "three_segment" }, { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  const geostation::RasterImage in = geostation::readRaster( input.toStdString() ), out = geostation::readRaster( output.toStdString() );
  QVERIFY( out.geoTransform.has_value() );
  QCOMPARE( ( *out.geoTransform )[0], 400000.0 );
  QCOMPARE( ( *out.geoTransform )[1], 0.5 );
  QVERIFY( out.crsWkt.find( "32633" ) != std::string::npos );
  // eq. 4.7 with a = mean, b = mean + 30, a' = 150: the darkest pixel goes to 0, the mean to 150, the brightest to 255
  const double mean = cv::mean( in.pixels )[0];
  QCOMPARE( out.pixels.at<uint8_t>( 0, 0 ), uint8_t( 0 ) );
  QCOMPARE( out.pixels.at<uint8_t>( 3, 63 ), uint8_t( 255 ) );
  const int c = static_cast<int>( std::ceil( mean ) ) - 40; // first column at or above the mean (row 0)
  QVERIFY( std::abs( out.pixels.at<uint8_t>( 0, c ) - ( ( 40 + c ) - mean + 150 ) ) <= 0.5 + 1e-9 );
}

void TestEnhanceImageAlgorithm::sixteenBitRgbWindow()
{
  const QString input = raster( "rgb16.tif", 3, GDT_UInt16, false ); // pixel space: x = col, y = -row
  const QString output = mDir.filePath( "rgb16_enhanced.tif" );
  RecordingFeedback feedback;
  bool ok = false;
  run( { { "INPUT", input }, { "METHOD", "linear" }, { "WINDOW", "10,30,-15,-5 []" }, { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  const geostation::RasterImage in = geostation::readRaster( input.toStdString() ), out = geostation::readRaster( output.toStdString() );
  QCOMPARE( out.pixels.type(), CV_16UC3 );
  QCOMPARE( out.pixels.at<cv::Vec3w>( 0, 0 ), in.pixels.at<cv::Vec3w>( 0, 0 ) ); // outside the window
  double lo = 0, hi = 0;
  cv::minMaxLoc( out.pixels( cv::Rect( 10, 5, 20, 10 ) ).reshape( 1 ), &lo, &hi );
  QCOMPARE( lo, 0.0 );
  QCOMPARE( hi, 65535.0 );
}

void TestEnhanceImageAlgorithm::badInputLeavesNoOutput()
{
  const QString input = raster( "float.tif", 1, GDT_Float32, true );
  const QString output = mDir.filePath( "float_enhanced.tif" );
  RecordingFeedback feedback;
  bool ok = true;
  run( { { "INPUT", input }, { "METHOD", "equalise" }, { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( ' ' ).contains( "8- and 16-bit unsigned images are supported" ), qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( output ) );
  // (four bands of bytes are RGB + alpha in a GeoTIFF, and read; five are not an image GeoStation knows)
  const QString fiveBands = raster( "five.tif", 5, GDT_Byte, false );
  run( { { "INPUT", fiveBands }, { "METHOD", "equalise" }, { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY( !QFile::exists( output ) );
}

int main( int argc, char **argv )
{
  return runQgisTests<TestEnhanceImageAlgorithm>( argc, argv );
}

#include "testenhanceimagealgorithm.moc"
