"""Studies made of many closed-loop runs: the compression study of Figure 6, sensitivity."""
