/***************************************************************************
  outputsink.h - how every algorithm writes its tables and counts outcomes
  -------------------------------------------------------------------------
  An output opened, written and closed the same way in every algorithm: a
  destination that cannot be opened and a feature that cannot be written
  are one sentence each (QgsProcessingException, naming the output);
  closing flushes it and, where rows may lack a geometry, stores those as
  NULL (processingblock.h: storeMissingGeometriesAsNull). And the tally of
  per-row outcomes ("ok 12, outside 3") the algorithms report.
 ***************************************************************************/
#ifndef OUTPUTSINK_H
#define OUTPUTSINK_H

#include <memory>

#include <QMap>
#include <QString>
#include <QVariantMap>

#include <qgsfeature.h>
#include <qgsfeaturesink.h>

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{
  class GEOSTATION_PROCESSING_EXPORT OutputSink
  {
    public:
      //! `sink` as parameterAsSink() gave it (null: it could not be opened - a sentence naming `name` is thrown). Closing twice is harmless; adding after close() throws.
      OutputSink( QgsFeatureSink *sink, const QString &destination, const QVariantMap &parameters, const QString &name );

      void add( QgsFeature &feature );
      void add( QgsFeatureList &features );
      //! Where it is written (the algorithm's result for the output).
      const QString &destination() const { return mDestination; }

      /**
       * Flushes and closes the output; `nullGeometries`: rows without a
       * geometry are stored as NULL (a GeoPackage would hold them empty).
       * Returns the destination, for the algorithm's results.
       */
      QString close( bool nullGeometries = false );

    private:
      void requireOpen() const;

      std::unique_ptr<QgsFeatureSink> mSink;
      QString mDestination;
      QVariantMap mParameters;
      QString mName;
  };

  //! How many rows had each outcome, in the order of the outcomes' names.
  class GEOSTATION_PROCESSING_EXPORT StatusTally
  {
    public:
      void add( const QString &status ) { ++mCounts[status]; }
      //! "lsm 40, no_peak 2": for the algorithm's closing line.
      QString text() const;

    private:
      QMap<QString, long> mCounts;
  };
} // namespace GeoStationProcessing

#endif // OUTPUTSINK_H
