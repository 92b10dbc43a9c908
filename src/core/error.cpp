#include "deepsea/core/error.h"
// Exceptions are header-only; this unit anchors the target.
