/* railride: lateral dynamics and ride comfort of high-speed trains.
 * Pipeline: vehicle file -> elements (system) -> M, C, K, B (model) ->
 * modal analysis / frequency response (PEM) / time simulation -> comfort.
 * The headers cite docs/model.md, docs/contact.md, docs/vertical.md and
 * docs/cli.md: installed beside the library in share/doc/railride/. */
#ifndef RAILRIDE_H
#define RAILRIDE_H

#include "railride/common.h"
#include "railride/error.h"
#include "railride/units.h"
#include "railride/sdf.h"
#include "railride/vehicle.h"
#include "railride/vertical.h"
#include "railride/system.h"
#include "railride/model.h"
#include "railride/modal.h"
#include "railride/stability.h"
#include "railride/damper.h"
#include "railride/spectrum.h"
#include "railride/pem.h"
#include "railride/ride.h"
#include "railride/comfort.h"
#include "railride/expm.h"
#include "railride/timesim.h"
#include "railride/design.h"
#include "railride/nsga2.h"
#include "railride/problem.h"
#include "railride/nonlinear.h"
#include "railride/profile.h"
#include "railride/contact.h"
#include "railride/layout.h"
#include "railride/version.h"
#endif
