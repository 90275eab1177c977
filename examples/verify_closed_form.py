"""Check your own closed form for g against ganzfeld: here K&P's printed law of vignetting of
Minnaert's BRDF with xi = 1, g = (j·n)/pi (pi - arccos(i·n) + (i·n) sqrt(1 - (i·n)^2)), over the
sky's pole from the nadir to the zenith. Run: scripts/python examples/verify_closed_form.py"""
import numpy as np
import ganzfeld

mu_i, mu_j = np.linspace(-1, 1, 201), 0.6                 # i·n of the sky's pole, j·n of the eye
mine = mu_j / np.pi * (np.pi - np.arccos(mu_i) + mu_i * np.sqrt(1 - mu_i**2))
g = ganzfeld.Model("minnaert:xi=1").g(cos_theta_i=mu_i, cos_theta_j=mu_j, tol=1e-12)
gap = np.abs(mine - g.value)
print(f"largest |mine - ganzfeld| = {gap.max():.2e}, ganzfeld's stated error <= {g.error.max():.2e}; "
      f"the gap exceeds the stated error at {(gap > g.error).sum()} of {gap.size} poles")
try:
    import matplotlib.pyplot as plt
    plt.semilogy(mu_i, np.maximum(gap, 1e-18), ".", label="|mine - ganzfeld|")
    plt.semilogy(mu_i, g.error, label="ganzfeld's stated error")
    plt.xlabel("i·n (the sky's pole)"), plt.legend(), plt.savefig("verify_closed_form.png")
    print("wrote verify_closed_form.png")
except ImportError:
    print("(matplotlib is not installed: no plot)")
