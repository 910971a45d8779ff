"""Signalling-panel controller of conde_sim: panel pictures, signal names, schedules."""
