G8 G21 (metric (mm)) G18
