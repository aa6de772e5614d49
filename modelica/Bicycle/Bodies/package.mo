within Bicycle;
package Bodies "Rigid bodies of the Whipple bicycle with their mass properties (Meijaard et al. 2007 conventions)"
  annotation(Documentation(info = "<html>
<p>The four rigid bodies of the Whipple bicycle model as used by J. P. Meijaard, J. M. Papadopoulos,
A. Ruina and A. L. Schwab, <em>Linearized dynamics equations for the balance and steer of a bicycle:
a benchmark and review</em>, Proc. R. Soc. A 463 (2007) 1955-1982: rear wheel R, rear frame B with
the rigidly attached rider, front frame H (fork and handlebar) and front wheel F.</p>
<p>Conventions (Meijaard 2007, <b>not</b> the ISO 8855 axes of the rest of this library): axes x
forward, y to the right, z <b>down</b>, origin at the rear-wheel contact point of the upright
bicycle with zero steer; centre-of-mass coordinates x, z in these axes (z &lt; 0 above the ground);
inertia-tensor elements about the body's own centre of mass in these axes, the product element
Ixz = -integral(x z dm) being the tensor element; wheels are axisymmetric (Izz = Ixx).</p>
<p>Each body also provides its first moments of mass and its inertia-tensor elements Jxx, Jxz, Jzz
about axes through the rear contact point (parallel-axis theorem); the bicycle assemblies sum
these to the totals of Meijaard's Appendix A.</p>
</html>"));
end Bodies;
