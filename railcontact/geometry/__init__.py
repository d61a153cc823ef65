"""Geometry layer: wheelset on track, contact search, gap functions, tables."""

from .contact import ContactGeometry
from .search import WheelsetContact, find_contact
from .tables import contact_table, equivalent_conicity
from .track import Track, Wheelset, WheelsetPose

__all__ = ["ContactGeometry", "WheelsetContact", "find_contact", "contact_table",
           "equivalent_conicity", "Track", "Wheelset", "WheelsetPose"]
