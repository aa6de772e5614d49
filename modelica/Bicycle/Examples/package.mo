within Bicycle;
package Examples "Runnable examples with experiment settings"
end Examples;
