within Bicycle.Mechanics.Joints;
partial model PartialRevolute "Revolute joint: frame_b turns relative to frame_a about a body-fixed axis by one of the generalized coordinates"
  constant Integer n = 6 "Number of generalized speeds";
  constant Real sel[n] "Selects the joint's generalized coordinate and speed (the unit vector of its index)";
  parameter Real nx(final unit = "1") = 0 "Axis (unit vector): x component in frame_a axes";
  parameter Real ny(final unit = "1") = 1 "Axis (unit vector): y component in frame_a axes";
  parameter Real nz(final unit = "1") = 0 "Axis (unit vector): z component in frame_a axes";
  Bicycle.Mechanics.Interfaces.Frame frame_a(n = n) "Frame the joint is fixed to";
  Bicycle.Mechanics.Interfaces.Frame frame_b(n = n) "Frame that turns about the axis";
  Bicycle.Units.Angle phi "Rotation angle of frame_b relative to frame_a about the axis";
  Bicycle.Units.AngularVelocity omega "Rotation rate der(phi)";
  Bicycle.Units.Torque tau "Torque on frame_b about the axis (and -tau on frame_a)";
protected
  Real selq[n] "sel .* q (rad)";
  Real selu[n] "sel .* u (rad/s)";
  Real e[3] "Axis in ground axes";
  Real Rrel[3, 3] "Orientation of frame_b relative to frame_a (Rodrigues' formula)";
  Real we[3] "w x e (1/s)";
equation
  for j in 1:n loop
    selq[j] = sel[j]*frame_a.q[j];
    selu[j] = sel[j]*frame_a.u[j];
  end for;
  phi = sum(selq);
  omega = sum(selu);
  for i in 1:3 loop
    e[i] = frame_a.R[i, 1]*nx + frame_a.R[i, 2]*ny + frame_a.R[i, 3]*nz;
  end for;
  Rrel[1, 1] = cos(phi) + (1 - cos(phi))*nx*nx;
  Rrel[1, 2] = (1 - cos(phi))*nx*ny - sin(phi)*nz;
  Rrel[1, 3] = (1 - cos(phi))*nx*nz + sin(phi)*ny;
  Rrel[2, 1] = (1 - cos(phi))*ny*nx + sin(phi)*nz;
  Rrel[2, 2] = cos(phi) + (1 - cos(phi))*ny*ny;
  Rrel[2, 3] = (1 - cos(phi))*ny*nz - sin(phi)*nx;
  Rrel[3, 1] = (1 - cos(phi))*nz*nx - sin(phi)*ny;
  Rrel[3, 2] = (1 - cos(phi))*nz*ny + sin(phi)*nx;
  Rrel[3, 3] = cos(phi) + (1 - cos(phi))*nz*nz;
  frame_b.R = frame_a.R*Rrel;
  frame_b.r = frame_a.r;
  frame_b.Vp = frame_a.Vp;
  frame_b.a0 = frame_a.a0;
  frame_b.q = frame_a.q;
  frame_b.u = frame_a.u;
  frame_b.w = frame_a.w + e*omega;
  for j in 1:n loop
    frame_b.Wp[1, j] = frame_a.Wp[1, j] + sel[j]*e[1];
    frame_b.Wp[2, j] = frame_a.Wp[2, j] + sel[j]*e[2];
    frame_b.Wp[3, j] = frame_a.Wp[3, j] + sel[j]*e[3];
  end for;
  we[1] = frame_a.w[2]*e[3] - frame_a.w[3]*e[2];
  we[2] = frame_a.w[3]*e[1] - frame_a.w[1]*e[3];
  we[3] = frame_a.w[1]*e[2] - frame_a.w[2]*e[1];
  frame_b.al0 = frame_a.al0 + we*omega;
  // Massless joint: the flows pass through; the joint torque is the generalized force tau of its coordinate
  zeros(n, n) = frame_a.M + frame_b.M;
  tau*sel = frame_a.f + frame_b.f;
  0 = frame_a.Ep + frame_b.Ep;
  annotation(Documentation(info = "<html><p>frame_b is frame_a turned by the angle <code>phi = q[k]</code>
about the unit axis <code>{nx, ny, nz}</code> (frame_a axes), where <code>sel</code> is the unit vector
of index <code>k</code>. The column <code>k</code> of the partial angular velocities gains the axis
<code>e</code> (ground axes), the angular acceleration remainder gains <code>(w x e)*omega</code>. A torque
<code>tau</code> on frame_b (reaction on frame_a) is the generalized force <code>tau</code> of coordinate
<code>k</code>. Extending classes give the equation for <code>tau</code>.</p></html>"));
end PartialRevolute;
