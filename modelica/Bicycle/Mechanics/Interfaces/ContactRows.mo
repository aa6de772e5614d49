within Bicycle.Mechanics.Interfaces;
connector ContactRows "Rolling contact with the ground: velocity of the wheel's material contact point B*u, its acceleration remainder, contact point position and velocity"
  constant Integer n = 6 "Number of generalized speeds";
  Real B[3, n] "Partial velocities of the wheel's material contact point (ground axes): its velocity is B*u (m)";
  Real b0[3] "Acceleration remainder of the material contact point: its acceleration is B*der(u) + b0 (m/s2)";
  Real p[3] "Position of the geometric contact point (ground axes) (m)";
  Real v[3] "Velocity of the geometric contact point (it moves over the ground and around the tyre) (m/s)";
  annotation(Documentation(info = "<html><p>Rolling without slip means <code>B*u = 0</code> (three
nonholonomic constraints; the vertical one is the rate of the holonomic constraint
<code>p[3] = 0</code>) and, differentiated, <code>B*der(u) + b0 = 0</code>. A wheel computes these
rows; the root (<code>Ground</code>) imposes them.</p></html>"));
end ContactRows;
