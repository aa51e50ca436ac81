"""From a case, a MoorDyn deck or a network to one Model.
"""
