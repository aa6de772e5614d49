within Bicycle.Mechanics.Interfaces;
connector WheelContact "Rolling contact of a wheel with the ground, the wheel's side (output): where the contact point is and how the wheel's material point there moves"
  constant Integer n = 6 "Number of generalized speeds of the system";
  output Bicycle.Units.Position rho[3] "Vector from the wheel centre to the contact point (ground axes)";
  output Bicycle.Units.Position p[3] "Position of the geometric contact point (ground axes)";
  output Bicycle.Units.Velocity v[3] "Velocity of the geometric contact point (it moves over the ground and around the tyre)";
  output Bicycle.Units.Length Bc[3, n] "Partial velocities of the material contact point relative to the wheel centre: w_wheel x rho = Bc*u";
  output Bicycle.Units.Acceleration bc0[3] "Acceleration remainder of the material contact point relative to the wheel centre";
  output Bicycle.Units.Length B[3, n] "Partial velocities of the material contact point: its velocity is B*u";
  output Bicycle.Units.Acceleration b0[3] "Acceleration remainder of the material contact point: its acceleration is B*du + b0";
  annotation(Documentation(info = "<html><p>Rolling without slip means <code>B*u = 0</code> (three
nonholonomic constraints; the vertical one is the rate of the holonomic constraint
<code>p[3] = 0</code>) and, differentiated, <code>B*du + b0 = 0</code>. A wheel computes these rows
from its hub's kinematics; the ground
(<a href=\"modelica://Bicycle.Mechanics.Ground\">Ground</a>, through a
<a href=\"modelica://Bicycle.Mechanics.Interfaces.GroundContact\">GroundContact</a>) imposes them.
The rows relative to the wheel centre (<code>Bc</code>, <code>bc0</code>) let the ground place the
wheel that carries the rear frame: its centre moves so that its contact point does not.</p>
<p>A signal connector (every variable causal): nothing is summed over a connection.</p></html>"));
end WheelContact;
