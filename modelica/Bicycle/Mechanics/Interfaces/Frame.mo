within Bicycle.Mechanics.Interfaces;
connector Frame "Body-fixed frame with its kinematics in the generalized speeds; flows: generalized mass matrix, forces and potential energy of the bodies beyond it"
  constant Integer n = 6 "Number of generalized speeds";
  Real R[3, 3] "Orientation: the columns are the frame's x, y, z axes resolved in ground axes";
  Real r[3] "Position of the frame origin (ground axes; the ground is z = 0, z down) (m)";
  Real w[3] "Angular velocity of the frame (ground axes) (rad/s)";
  Real Wp[3, n] "Partial angular velocities: w = Wp*u";
  Real al0[3] "Angular acceleration remainder (rad/s2): der(w) = Wp*der(u) + al0";
  Real Vp[3, n] "Partial velocities of the origin: der(r) = Vp*u (m)";
  Real a0[3] "Acceleration remainder of the origin: der(der(r)) = Vp*der(u) + a0 (m/s2)";
  Real q[n] "Generalized coordinates (der(q[k]) = u[k]) (rad)";
  Real u[n] "Generalized speeds (rad/s)";
  flow Real M[n, n] "Generalized mass matrix of the bodies beyond the frame: sum of m Vp'Vp + Wp' I Wp (kg.m2)";
  flow Real f[n] "Generalized forces of the bodies beyond the frame without the der(u) terms: sum of Vp'(F - m a0) + Wp'(T - I al0 - w x I w) (N.m)";
  flow Real Ep(final quantity = "Energy", final unit = "J") "Gravitational potential energy of the bodies beyond the frame (zero at the ground)";
  annotation(Documentation(info = "<html>
<p>The potential variables describe the motion of the frame as a function of the generalized
coordinates <code>q</code> and speeds <code>u</code> (all vectors in ground axes):
angular velocity <code>w = Wp*u</code>, angular acceleration <code>Wp*der(u) + al0</code>, velocity of
the origin <code>Vp*u</code>, its acceleration <code>Vp*der(u) + a0</code>. The flow variables are
sums over the bodies attached beyond the frame: a body adds <code>m Vp'Vp + Wp' I Wp</code> to
<code>M</code> and its generalized active plus inertia forces without the <code>der(u)</code> terms to
<code>f</code>, so that Kane's equations of the whole system are <code>M*der(u) = f</code> (before the
constraints are applied).</p>
</html>"));
end Frame;
