within Bicycle.Mechanics.Rider;
model Ground "Root of a bicycle with the rider's hip hinge on flat ground: 7 generalized coordinates and speeds (4 independent), dependent-speed elimination, Kane's equations"
  extends Bicycle.Mechanics.PartialGround(
    n = 7,
    ni = 4,
    S = [1, 0, 0, 0; 0, 1, 0, 0; 0, 0, 1, 0; 0, 0, 0, 0; 0, 0, 0, 0; 0, 0, 0, 0; 0, 0, 0, 1],
    D = [0, 0, 0; 0, 0, 0; 0, 0, 0; 1, 0, 0; 0, 1, 0; 0, 0, 1; 0, 0, 0]);
  parameter Bicycle.Units.Angle beta0 = 0 "Initial lean angle of the upper body relative to the rear frame";
  parameter Bicycle.Units.AngularVelocity u_beta0 = 0 "Initial lean rate of the upper body";
  // the inputs and the states are declared here (not in PartialGround or the assembly), in the order of the flat model's FMU
  Bicycle.Interfaces.RealInput T_phi(final quantity = "Torque", final unit = "N.m") "Roll torque T_phi on the rear frame about the (horizontal) roll axis, positive tending to lean right (disturbance)";
  Bicycle.Interfaces.RealInput T_beta(final quantity = "Torque", final unit = "N.m") "Lean torque T_beta of the rider between rear frame and upper body, positive tending to lean the upper body right (the assembly connects it to the hip hinge)";
  output Bicycle.Units.Position x(start = x0, fixed = true) "x coordinate (forward at yaw 0) of the rear contact point";
  output Bicycle.Units.Position y(start = y0, fixed = true) "y coordinate (right at yaw 0) of the rear contact point: lateral position";
  output Bicycle.Units.Angle psi(start = psi0, fixed = true) "Yaw angle psi of the rear frame, positive turning right";
  output Bicycle.Units.Angle phi(start = phi0, fixed = true) "Roll angle phi of the rear frame, positive leaning right";
  output Bicycle.Units.Angle theta(start = theta_guess, fixed = false) "Pitch angle theta of the rear frame, positive nose up (0: upright, zero steer)";
  output Bicycle.Units.Angle delta(start = delta0, fixed = true) "Steer angle delta, positive steering right";
  output Bicycle.Units.Angle thetaR(start = thetaR0, fixed = true) "Rear wheel angle relative to the rear frame";
  output Bicycle.Units.Angle thetaF(start = thetaF0, fixed = true) "Front wheel angle relative to the front frame";
  output Bicycle.Units.Angle beta(start = beta0, fixed = true) "Lean angle beta of the upper body relative to the rear frame, positive leaning right";
  output Bicycle.Units.AngularVelocity u_phi(start = u_phi0, fixed = true) "Roll rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_delta(start = u_delta0, fixed = true) "Steer rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_R(start = u_R0, fixed = true) "Rear wheel rate relative to the rear frame (independent speed; negative rolling forward)";
  output Bicycle.Units.AngularVelocity u_beta(start = u_beta0, fixed = true) "Lean rate of the upper body (independent speed)";
equation
  // Generalized coordinates and speeds (order: roll, steer, rear wheel, yaw, pitch, front wheel, lean)
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
  // Coordinate 7: the lean angle, the fourth independent speed; the rear frame does not turn with it
  rear.q[7] = beta;
  rear.u[7] = u_beta;
  ui[4] = u_beta;
  dui[4] = der(u_beta);
  der(beta) = u_beta;
  for i in 1:3 loop
    rear.Wp[i, 7] = 0;
  end for;
  annotation(Documentation(info = "<html>
<p>The root of the generalized-coordinate components for a bicycle whose rider leans the upper
body about a hip hinge: <a href=\"modelica://Bicycle.Mechanics.PartialGround\">Bicycle.Mechanics.PartialGround</a>
(which writes the equations of <a href=\"modelica://Bicycle.Mechanics.Ground\">Ground</a> for any
number of speeds) with the lean angle <code>beta</code> of the upper body relative to the rear frame as a seventh
generalized coordinate and its rate <code>u_beta</code> as a fourth independent speed:
<code>q = {phi, delta, thetaR, psi, theta, thetaF, beta}</code>,
<code>u = {u_phi, u_delta, u_R, u_psi, u_theta, u_F, u_beta}</code>, <code>der(q) = u</code>. The
hinge component selects coordinate 7 (<code>sel = {0, 0, 0, 0, 0, 0, 1}</code>); the other
components select the same coordinates as in the bicycle without the hinge, with one more zero.</p>
<p>As there: the connector <code>rear</code> gives the rear frame's orientation and angular
velocity, the rear wheel's rolling rows (imposed: <code>B = 0</code>, <code>b0 = 0</code>) determine
the motion of the rear axle, the front wheel's rows <code>Bi*ui + Bd*ud = 0</code> determine the
dependent speeds <code>ud = Ad*ui</code> and <code>Bd*ad0 = -b0</code> their acceleration remainder, and
Kane's equations of the constrained system are <code>T'*Mt*T*der(ui) = T'*(ft - Mt*D*ad0)</code>
(here a 4 x 4 system). The hinge speed does not enter the front contact rows (nothing between the
ground and the front wheel moves with it), so <code>Ad[:, 4] = 0</code>.</p>
<p>The energy <code>E</code> includes the potential energy that components report through the
connector (gravity, the hinge spring). The initial pitch solves <code>residual = 0</code>, starting
from <code>theta_guess</code>.</p>
</html>"));
end Ground;
