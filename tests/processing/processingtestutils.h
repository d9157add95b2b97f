// Shared by the provider tests: a feedback that records messages, and the
// main() that runs a QtTest object inside an initialised QgsApplication.
#ifndef GEOSTATION_PROCESSINGTESTUTILS_H
#define GEOSTATION_PROCESSINGTESTUTILS_H

#include <QStringList>
#include <QtTest/QtTest>

#include <qgsapplication.h>
#include <qgsprocessingfeedback.h>

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
