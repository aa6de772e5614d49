within Bicycle.Mechanics;
model Ground "Root of a bicycle on flat ground: six generalized coordinates and speeds (three independent), dependent-speed elimination, Kane's equations"
  extends Bicycle.Mechanics.PartialGround(
    n = 6,
    ni = 3,
    S = [1, 0, 0; 0, 1, 0; 0, 0, 1; 0, 0, 0; 0, 0, 0; 0, 0, 0],
    D = [0, 0, 0; 0, 0, 0; 0, 0, 0; 1, 0, 0; 0, 1, 0; 0, 0, 1]);
  Bicycle.Interfaces.RealInput T_phi(final quantity = "Torque", final unit = "N.m") "Roll torque T_phi on the rear frame about the (horizontal) roll axis, positive tending to lean right (disturbance)";
  output Bicycle.Units.Position x(start = x0, fixed = true) "x coordinate (forward at yaw 0) of the rear contact point";
  output Bicycle.Units.Position y(start = y0, fixed = true) "y coordinate (right at yaw 0) of the rear contact point: lateral position";
  output Bicycle.Units.Angle psi(start = psi0, fixed = true) "Yaw angle psi of the rear frame, positive turning right";
  output Bicycle.Units.Angle phi(start = phi0, fixed = true) "Roll angle phi of the rear frame, positive leaning right";
  output Bicycle.Units.Angle theta(start = theta_guess, fixed = false) "Pitch angle theta of the rear frame, positive nose up (0: upright, zero steer)";
  output Bicycle.Units.Angle delta(start = delta0, fixed = true) "Steer angle delta, positive steering right";
  output Bicycle.Units.Angle thetaR(start = thetaR0, fixed = true) "Rear wheel angle relative to the rear frame";
  output Bicycle.Units.Angle thetaF(start = thetaF0, fixed = true) "Front wheel angle relative to the front frame";
  output Bicycle.Units.AngularVelocity u_phi(start = u_phi0, fixed = true) "Roll rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_delta(start = u_delta0, fixed = true) "Steer rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_R(start = u_R0, fixed = true) "Rear wheel rate relative to the rear frame (independent speed; negative rolling forward)";
equation
  // Generalized coordinates and speeds (order: roll, steer, rear wheel, yaw, pitch, front wheel)
  rear.q[1] = phi;
  rear.q[2] = delta;
  rear.q[3] = thetaR;
  rear.q[4] = psi;
  rear.q[5] = theta;
  rear.q[6] = thetaF;
  rear.u[1] = u_phi;
  rear.u[2] = u_delta;
  rear.u[3] = u_R;
  dui[1] = der(u_phi);
  dui[2] = der(u_delta);
  dui[3] = der(u_R);
  der(x) = rearContact.v[1];
  der(y) = rearContact.v[2];
  der(psi) = u_psi;
  der(phi) = u_phi;
  der(theta) = u_theta;
  der(delta) = u_delta;
  der(thetaR) = u_R;
  der(thetaF) = u_F;
  rearContact.p[1] = x;
  rearContact.p[2] = y;
  // the roll torque is the generalized force of the roll coordinate
  ft[1] = rear.f[1] + T_phi;
  annotation(Documentation(info = "<html>
<p>The root of the generalized-coordinate components for a bicycle (Kane's method):
<a href=\"modelica://Bicycle.Mechanics.PartialGround\">PartialGround</a> with the six coordinates
<code>q = {phi, delta, thetaR, psi, theta, thetaF}</code> and speeds
<code>u = {u_phi, u_delta, u_R, u_psi, u_theta, u_F}</code>, <code>der(q) = u</code>; the independent
speeds are <code>ui = {u_phi, u_delta, u_R}</code>, the dependent ones <code>u_psi, u_theta,
u_F</code> follow from the front wheel's rolling constraints. A bicycle assembly
(<a href=\"modelica://Bicycle.Bicycles.Whipple\">Whipple</a>) extends it and connects its bodies to
the connectors <code>rear</code>, <code>rearContact</code> and <code>frontContact</code>.</p>
</html>"));
end Ground;
