/***************************************************************************
  tracedline.h - a traced line as the operator builds it, part by part
  -------------------------------------------------------------------------
  Tracing stops where the operator is needed (a gap too large, a sharp
  turn, a line hidden by a car). The operator then clicks on the line
  where it goes on, and tracing continues from there; or takes back the
  last station's part when it went wrong; or finishes. TracedLine keeps
  the vertices of all those traces as one line along the run:
  - append(): a new trace's vertices join at the end; those that lie
    behind the line's end (along its last direction) are dropped, so a
    restart a little before where the line stopped does not fold it back.
  - takeBackLastStation(): the vertices of the last station go (all of
    them: a station's part may hold a few of the previous station's
    vertices where it had none of its own).
  No Qt: the Multiview's Trace tool and tests use the same code.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_TRACEDLINE_H
#define GEOSTATION_TRACING_TRACEDLINE_H

#include <string>
#include <vector>

#include "tracing/roadtracer.h"

namespace geostation
{

  class TracedLine
  {
    public:
      /**
       * Appends a trace's vertices (see the file comment); returns how many
       * joined the line.
       */
      size_t append( const std::vector<TracedVertex> &vertices );
      size_t append( const RoadTraceSummary &trace ) { return append( trace.vertices ); }

      /**
       * Removes the vertices of the last station (the one whose part starts
       * last along the line); returns that station's id ("" when the line
       * is empty).
       */
      std::string takeBackLastStation();

      void clear() { mVertices.clear(); }
      bool empty() const { return mVertices.empty(); }
      const std::vector<TracedVertex> &vertices() const { return mVertices; }
      std::vector<Eigen::Vector3d> points() const;

      double lengthM() const;
      //! Largest vertex sigma (any axis), metres.
      double sigmaMaxM() const;
      //! The stations the line's vertices come from, in the line's order, each once.
      std::vector<std::string> stationIds() const;

    private:
      std::vector<TracedVertex> mVertices;
  };

} // namespace geostation

#endif // GEOSTATION_TRACING_TRACEDLINE_H
