// Shared by the provider tests: a feedback that records messages, and the
// main() that runs a QtTest object inside an initialised QgsApplication.
#ifndef GEOSTATION_PROCESSINGTESTUTILS_H
#define GEOSTATION_PROCESSINGTESTUTILS_H

#include <optional>

#include <QDir>
#include <QFile>
#include <QStringList>
#include <QXmlStreamReader>
#include <QtTest/QtTest>

#include <qgsapplication.h>
#include <qgsprocessingfeedback.h>

#include "simulation/surveysimulator.h"

//! Collects what an algorithm reports, so tests can read its messages.
class RecordingFeedback : public QgsProcessingFeedback
{
  public:
    void reportError( const QString &error, bool fatal = false ) override
    {
      errors << error;
      QgsProcessingFeedback::reportError( error, fatal );
    }
    void pushWarning( const QString &warning ) override
    {
      warnings << warning;
      QgsProcessingFeedback::pushWarning( warning );
    }
    void pushInfo( const QString &info ) override
    {
      infos << info;
      QgsProcessingFeedback::pushInfo( info );
    }
    QStringList errors, warnings, infos;
};

//! The aerial_stereo preset's pair of 2 stations at 0.5 m (seed 3, noise 4) simulated into `dir`: what the road tests run on.
inline void simulateAerialRoadPair( const QString &dir )
{
  geostation::SimulationOptions options;
  options.preset = geostation::SurveyPreset::AerialStereo;
  options.outputDir = dir.toStdString();
  options.stations = 2;
  options.groundPixelSizeM = 0.5;
  options.seed = 3;
  options.degradation.noiseSigma = 4.0;
  geostation::simulateSurvey( options );
}

//! The folder GEOSTATION_TEST_ARTIFACTS names (made), where tests leave the user guide's pictures (scripts/screenshots.sh); none when unset.
inline std::optional<QDir> testArtifacts()
{
  if ( !qEnvironmentVariableIsSet( "GEOSTATION_TEST_ARTIFACTS" ) )
    return std::nullopt;
  const QDir dir( qEnvironmentVariable( "GEOSTATION_TEST_ARTIFACTS" ) );
  QDir().mkpath( dir.path() );
  return dir;
}

//! What a REPORT_HTML page holds, read as XML (the page is written well-formed: unescaped text would break it).
struct HtmlReportShape
{
  QString error;              //!< empty when the file was read and well-formed
  QString title;
  QList<QStringList> rows;    //!< every table row's cells, header rows included
  int svgs = 0;
  int points = 0;                //!< the points of the residual plots
  int arrows = 0, redArrows = 0; //!< residual vectors long enough to be drawn (lines with an arrow head)
  int polylines = 0;
  int histogramCount = 0;     //!< values in the histograms (sum of the bars' counts)

  //! The first row whose first cell is `first`.
  QStringList row( const QString &first ) const
  {
    for ( const QStringList &r : rows )
      if ( !r.isEmpty() && r.first() == first )
        return r;
    return {};
  }
};

inline HtmlReportShape readHtmlReport( const QString &path )
{
  HtmlReportShape shape;
  QFile file( path );
  if ( !file.open( QIODevice::ReadOnly ) )
  {
    shape.error = QStringLiteral( "cannot open %1" ).arg( path );
    return shape;
  }
  QXmlStreamReader xml( &file );
  QStringList row;
  QString cell, title;
  bool inCell = false, inTitle = false, inBarTitle = false;
  while ( !xml.atEnd() )
  {
    xml.readNext();
    const QString name = xml.name().toString();
    if ( xml.isStartElement() )
    {
      if ( name == QLatin1String( "tr" ) )
        row.clear();
      else if ( name == QLatin1String( "td" ) || name == QLatin1String( "th" ) )
      {
        inCell = true;
        cell.clear();
      }
      else if ( name == QLatin1String( "svg" ) )
        ++shape.svgs;
      else if ( name == QLatin1String( "line" ) && xml.attributes().hasAttribute( QStringLiteral( "marker-end" ) ) )
      {
        ++shape.arrows;
        shape.redArrows += xml.attributes().value( QStringLiteral( "stroke" ) ) == QLatin1String( "#c0392b" );
      }
      else if ( name == QLatin1String( "circle" ) )
        ++shape.points;
      else if ( name == QLatin1String( "polyline" ) )
        ++shape.polylines;
      else if ( name == QLatin1String( "rect" ) && xml.attributes().value( QStringLiteral( "fill" ) ) == QLatin1String( "#1f5fa8" ) )
        inBarTitle = true;
      else if ( name == QLatin1String( "title" ) )
      {
        inTitle = true;
        title.clear();
      }
    }
    else if ( xml.isCharacters() )
    {
      if ( inCell )
        cell += xml.text();
      if ( inTitle )
        title += xml.text();
    }
    else if ( xml.isEndElement() )
    {
      if ( name == QLatin1String( "td" ) || name == QLatin1String( "th" ) )
      {
        row << cell.trimmed();
        inCell = false;
      }
      else if ( name == QLatin1String( "tr" ) )
        shape.rows << row;
      else if ( name == QLatin1String( "title" ) )
      {
        inTitle = false;
        if ( inBarTitle )
          shape.histogramCount += title.section( ':', -1 ).trimmed().toInt();
        else if ( shape.title.isEmpty() )
          shape.title = title;
        inBarTitle = false;
      }
    }
  }
  if ( xml.hasError() )
    shape.error = QStringLiteral( "%1 is not well-formed: %2 (line %3)" ).arg( path, xml.errorString() ).arg( xml.lineNumber() );
  return shape;
}

//! Runs the tests of T with QGIS initialised (no GUI).
template <typename T>
int runQgisTests( int argc, char **argv )
{
  QgsApplication app( argc, argv, false );
  QgsApplication::init();
  QgsApplication::initQgis();
  int result = 0;
  {
    // Destroyed before exitQgis(): it holds layers whose providers must still exist.
    T test;
    result = QTest::qExec( &test, argc, argv );
  }
  QgsApplication::exitQgis();
  return result;
}

#endif
