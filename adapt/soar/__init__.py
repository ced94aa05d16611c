"""The Soar engine: the real Soar kernel (PyPI ``soar-sml``) behind adapt's engine interface.

``adapt rules run --engine soar``, ``engine: soar`` in a scenario and
``adapt sweep --set engine=soar`` run the same rule files, scenarios and
traces on the Soar kernel instead of adapt's own engine
(:mod:`adapt.engine.interface`, ``docs/engines.md``).  Installing
``adapt[soar]`` brings the kernel.

* :mod:`adapt.soar.agent` -- :class:`SoarAgent`, the engine;
* :mod:`adapt.soar.process` -- the kernel's child process, crash detection,
  :func:`require_soar`;
* :mod:`adapt.soar.worker` -- the child's side, the one module that imports
  ``soar_sml``;
* :mod:`adapt.soar.recorder`, :mod:`adapt.soar.xmltrace` -- the kernel's XML
  trace turned into adapt's report and trace records;
* :mod:`adapt.soar.inputlink` -- input-link writes as SML input WMEs.

Nothing here is imported by :mod:`adapt.engine`; importing this package does
not load the kernel.
"""

from adapt.soar.agent import SoarAgent, SoarRules, trace_commands
from adapt.soar.process import INSTALL_HINT, KernelCrash, require_soar

__all__ = ["SoarAgent", "SoarRules", "KernelCrash", "require_soar", "trace_commands", "INSTALL_HINT"]
