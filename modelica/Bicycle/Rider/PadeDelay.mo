within Bicycle.Rider;
block PadeDelay "Neuromuscular delay exp(-s*tau) of the rider as a Pade approximation of order n"
  extends Bicycle.Icons.Block;
  parameter Bicycle.Units.Time tau(min = 1e-6) = 0.1 "Delay (0.1 s for steer torque, 0.3 s for upper-body lean)";
  parameter Integer n(min = 1, max = 10) = 2 "Order of the approximation (numerator and denominator degree); structural";
  Bicycle.Interfaces.RealInput u "Signal into the delay"
    annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  Bicycle.Interfaces.RealOutput y "Delayed signal"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
protected
  Real d[n + 1] "Denominator coefficient of s^(k-1), d[1] = 1 (the numerator's alternate in sign)";
  Real x[n](each start = 0, each fixed = true) "States of the controllable canonical form";
  Real feedback[n] "Running sums of d[k]*x[k]";
  Real output_[n] "Running sums of ((-1)^(k-1) - (-1)^n)*d[k]*x[k]";
equation
  // Pade coefficients: d[1] = 1, d[k] = d[k-1]*tau*(n-k+2)/((k-1)*(2n-k+2)). One loop defines all
  // of d (max() keeps the unused branch in range).
  for k in 1:n + 1 loop
    d[k] = if k == 1 then 1 else d[max(k - 1, 1)]*tau*(n - k + 2)/(max(k - 1, 1)*(2*n - k + 2));
  end for;
  for i in 1:n - 1 loop
    der(x[i]) = x[i + 1];
  end for;
  // Dot products as running sums (pymoca treats a[1:n]*x as a matrix product).
  feedback[1] = d[1]*x[1];
  output_[1] = (1 - (-1)^n)*d[1]*x[1];
  for k in 2:n loop
    feedback[k] = feedback[k - 1] + d[k]*x[k];
    output_[k] = output_[k - 1] + ((-1)^(k - 1) - (-1)^n)*d[k]*x[k];
  end for;
  der(x[n]) = u - feedback[n]/d[n + 1];
  y = output_[n]/d[n + 1] + (-1)^n*u;
  annotation(
    Icon(graphics = {
      Text(extent = {{-90, 60}, {90, -10}}, textString = "e^(-sτ)", textColor = {0, 0, 0}),
      Text(extent = {{-90, -30}, {90, -80}}, textString = "τ=%tau, n=%n", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Transfer function N(s)/D(s) with D(s) = sum d[k+1] s^k and N(s) = sum (-1)^k d[k+1] s^k, the
[n/n] Pade approximant of exp(-s tau) (identical to python-control's <code>pade(tau, n)</code>).
The order n fixes the number of states and is therefore fixed when the FMU is built.</p>
</html>"));
end PadeDelay;
