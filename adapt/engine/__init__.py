"""The production-rule engine: a faithful subset of Soar in pure Python.

Imports only the standard library and :mod:`adapt.errors`.
"""
