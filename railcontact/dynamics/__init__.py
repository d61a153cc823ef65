"""Dynamics layer: vehicle models running on a track with the contact models online.

- :mod:`~railcontact.dynamics.vehicle`: wheelset, bogie and full-vehicle models in
  track-following coordinates (Manchester benchmark vehicle preset), compiled
  right-hand side;
- :mod:`~railcontact.dynamics.route`: track design geometry (tangent, clothoid,
  curve, cant) and irregularities (ORE B176 spectra or a file);
- :mod:`~railcontact.dynamics.wheel_rail`: per-patch contact table from the geometry
  layer and the creep-force laws evaluated online;
- :mod:`~railcontact.dynamics.simulation`: time integration, linear stability
  (eigenvalues);
- :mod:`~railcontact.dynamics.scenario`: scenario files (vehicle, route, simulation)
  and Dask batches of them;
- :mod:`~railcontact.dynamics.wheelset`: the classical two-degree-of-freedom
  wheelset with tabulated geometry (verification of Klingel's wavelength);
- :mod:`~railcontact.dynamics.roller_rig`: a wheelset on a roller rig (the
  contact off the rollers' apexes with yaw, the rollers' speed in the creepages),
  its excited hunting and its critical speed against tangent track;
- :mod:`~railcontact.dynamics.contact_element`: the contact element of a multibody
  model (forces and torques of both rails on a wheelset from its pose and motion);
- :mod:`~railcontact.fmu`: that element as an FMI 3.0 co-simulation FMU
  (needs the ``fmu`` extra; not imported here).
"""

from .route import Irregularities, Route, erri_psd
from .scenario import simulate_batch
from .simulation import (Integration, amplitude_growth, critical_speed, simulate_vehicle,
                         state_matrix)
from .vehicle import MANCHESTER, Body, Element, VehicleModel
from .wheel_rail import WheelRailTable
from .wheelset import WheelsetModel, linear_matrix, simulate, wavelength
from .wheelset import critical_speed as wheelset_critical_speed

__all__ = ["WheelsetModel", "simulate", "wavelength", "linear_matrix",
           "wheelset_critical_speed", "VehicleModel", "Body", "Element", "MANCHESTER",
           "Route", "Irregularities", "erri_psd", "WheelRailTable", "simulate_vehicle", "Integration",
           "simulate_batch", "state_matrix", "critical_speed", "amplitude_growth"]
